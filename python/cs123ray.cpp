// cs123ray: ray's public API (include/ray/) as a Python module, through pybind11.
//
// Named cs123ray, not ray: `import ray` is the widely installed distributed-computing
// package on PyPI, and the course's scenefile format (CS123) names what this one renders.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

#include "ray/ray.h"

namespace py = pybind11;
namespace api = ray::api;

namespace {

// A scene with the warnings of its loading.
struct PyScene {
    api::Scene scene;
    std::vector<std::string> warnings;
};

api::Vec3 vec3(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }
std::array<double, 3> tuple3(const api::Vec3& v) { return {v.x, v.y, v.z}; }

api::LoadOptions loadOptions(const std::vector<std::filesystem::path>& searchPaths, bool strict, bool textures) {
    api::LoadOptions options;
    options.searchPaths = searchPaths;
    options.strict = strict;
    options.loadTextures = textures;
    return options;
}

template <class Enum>
Enum enumFromName(const std::string& name, const std::vector<std::pair<const char*, Enum>>& names, const char* what) {
    std::string known;
    for (const auto& [text, value] : names) {
        if (name == text) return value;
        known += (known.empty() ? "" : ", ") + std::string(text);
    }
    throw py::value_error(std::string(what) + " must be one of " + known + ", not '" + name + "'");
}

api::LightType lightType(const std::string& name) {
    return enumFromName<api::LightType>(name,
                                        {{"point", api::LightType::Point},
                                         {"directional", api::LightType::Directional},
                                         {"spot", api::LightType::Spot},
                                         {"area", api::LightType::Area}},
                                        "light type");
}

api::Shape shape(const std::string& name) {
    return enumFromName<api::Shape>(name,
                                    {{"cube", api::Shape::Cube},
                                     {"sphere", api::Shape::Sphere},
                                     {"cylinder", api::Shape::Cylinder},
                                     {"cone", api::Shape::Cone},
                                     {"torus", api::Shape::Torus},
                                     {"mesh", api::Shape::Mesh}},
                                    "shape");
}

// A 3x4 or 4x4 matrix (nested sequences or a NumPy array), row-major, object to world.
api::Transform transformFrom(const py::array_t<double, py::array::c_style | py::array::forcecast>& matrix) {
    if (matrix.ndim() != 2 || matrix.shape(1) != 4 || (matrix.shape(0) != 3 && matrix.shape(0) != 4))
        throw py::value_error("a transform is a 3x4 or 4x4 matrix");
    api::Transform t;
    auto m = matrix.unchecked<2>();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) t.m[r][c] = m(r, c);
    return t;
}

py::array_t<double> matrixOf(const api::Transform& t) {
    py::array_t<double> out({4, 4});
    auto m = out.mutable_unchecked<2>();
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m(r, c) = r < 3 ? t.m[r][c] : (c == 3 ? 1.0 : 0.0);
    return out;
}

template <class T>
std::vector<T> flat(const py::array_t<T, py::array::c_style | py::array::forcecast>& array, py::ssize_t columns,
                    const char* what) {
    if (array.size() == 0) return {};
    if (array.ndim() != 2 || array.shape(1) != columns)
        throw py::value_error(std::string(what) + " must be an N x " + std::to_string(columns) + " array");
    return std::vector<T>(array.data(), array.data() + array.size());
}

api::Settings settingsFrom(const py::kwargs& options, api::Settings s) {
    for (const auto& [key, value] : options) {
        const std::string name = py::str(key);
        if (name == "width") s.width = value.cast<int>();
        else if (name == "height") s.height = value.cast<int>();
        else if (name == "depth") s.depth = value.cast<int>();
        else if (name == "aa")
            s.antialias = enumFromName<api::Antialias>(value.cast<std::string>(),
                                                       {{"off", api::Antialias::Off},
                                                        {"course", api::Antialias::Course},
                                                        {"stratified", api::Antialias::Stratified},
                                                        {"adaptive", api::Antialias::Adaptive}},
                                                       "aa");
        else if (name == "samples") s.samples = value.cast<int>();
        else if (name == "seed") s.seed = value.cast<uint32_t>();
        else if (name == "area_samples") s.areaSamples = value.cast<int>();
        else if (name == "shutter") s.shutter = value.cast<double>();
        else if (name == "threshold") s.threshold = value.cast<double>();
        else if (name == "shadows") s.shadows = value.cast<bool>();
        else if (name == "reflections") s.reflections = value.cast<bool>();
        else if (name == "refraction") s.refraction = value.cast<bool>();
        else if (name == "textures") s.textures = value.cast<bool>();
        else if (name == "dof") s.depthOfField = value.cast<bool>();
        else if (name == "dof_mode")
            s.dofMode = enumFromName<api::DofMode>(value.cast<std::string>(),
                                                   {{"course", api::DofMode::Course}, {"disk", api::DofMode::Disk}},
                                                   "dof_mode");
        else if (name == "fresnel") s.fresnel = value.cast<bool>();
        else if (name == "course_meshes") s.courseMeshes = value.cast<bool>();
        else if (name == "texture_filter")
            s.textureFilter = enumFromName<api::TextureFilter>(value.cast<std::string>(),
                                                               {{"nearest", api::TextureFilter::Nearest},
                                                                {"bilinear", api::TextureFilter::Bilinear},
                                                                {"trilinear", api::TextureFilter::Trilinear}},
                                                               "texture_filter");
        else throw py::type_error("unknown render option '" + name + "'");
    }
    return s;
}

// Renders on a worker thread while this (Python's) thread waits, every 50 ms checking for
// signals (Ctrl-C: the frame is cancelled, its tiles in flight finish within about a
// second, and KeyboardInterrupt is raised) and reporting progress to the callback.
api::FrameStats renderWatched(api::Renderer& renderer, float* rgb, size_t floats, const py::object& progress) {
    std::atomic<bool> cancel{false};
    std::atomic<double> fraction{0};
    std::future<api::FrameStats> frame;
    {
        py::gil_scoped_release released;
        frame = std::async(std::launch::async, [&] {
            return renderer.render(rgb, floats, [&](double f) { fraction = f; }, &cancel);
        });
    }
    bool interrupted = false;
    double reported = -1;
    while (true) {
        std::future_status status;
        {
            py::gil_scoped_release released;
            status = frame.wait_for(std::chrono::milliseconds(50));
        }
        if (status == std::future_status::ready) break;
        if (!interrupted && PyErr_CheckSignals() != 0) {
            interrupted = true;
            cancel = true;
        }
        if (!interrupted && !progress.is_none() && fraction != reported) {
            reported = fraction;
            try {
                progress(reported);
            } catch (...) {
                cancel = true;  // the callback raised: stop the frame, then re-raise
                py::gil_scoped_release released;
                frame.wait();
                throw;
            }
        }
    }
    api::FrameStats stats = frame.get();  // rethrows the render's exception
    if (interrupted) throw py::error_already_set();
    if (!progress.is_none()) progress(1.0);
    return stats;
}

// Renders a frame as an H x W x 3 array: float32 (linear, unclamped) or uint8 (the bytes
// ray's 8-bit images hold).
py::array renderArray(api::Renderer& renderer, const std::string& dtype, const py::object& progress) {
    if (dtype != "float32" && dtype != "uint8") throw py::value_error("dtype must be 'float32' or 'uint8'");
    const api::Settings& s = renderer.settings();
    py::array_t<float> rgb({py::ssize_t(s.height), py::ssize_t(s.width), py::ssize_t(3)});
    renderWatched(renderer, rgb.mutable_data(), size_t(rgb.size()), progress);
    if (dtype == "float32") return rgb;
    py::array_t<uint8_t> bytes({py::ssize_t(s.height), py::ssize_t(s.width), py::ssize_t(3)});
    std::transform(rgb.data(), rgb.data() + rgb.size(), bytes.mutable_data(), api::toByte);
    return bytes;
}

void registerErrors(py::module_& m) {
    static py::exception<api::Error> error(m, "Error", PyExc_RuntimeError);
    static py::exception<api::InputError> inputError(m, "InputError", error.ptr());
    static py::exception<api::DeviceError> deviceError(m, "DeviceError", error.ptr());
    py::register_exception_translator([](std::exception_ptr thrown) {
        try {
            if (thrown) std::rethrow_exception(thrown);
        } catch (const api::InputError& e) {
            // InputError carries .file and .line (0 where the problem has no line).
            py::object instance = py::reinterpret_borrow<py::object>(inputError.ptr())(e.what());
            instance.attr("file") = e.file();
            instance.attr("line") = e.line();
            PyErr_SetObject(inputError.ptr(), instance.ptr());
        } catch (const api::DeviceError& e) {
            deviceError(e.what());
        } catch (const api::Error& e) {
            error(e.what());
        }
    });
}

}  // namespace

PYBIND11_MODULE(cs123ray, m) {
    m.doc() = "ray, the CS123 scenefile ray tracer: load or build a scene, render it to a NumPy array.";
    registerErrors(m);

    py::class_<api::Transform>(m, "Transform", "An object-to-world affine transform (compose with @).")
        .def(py::init<>())
        .def(py::init(&transformFrom), py::arg("matrix"))
        .def_static("translate", [](double x, double y, double z) { return api::Transform::translate({x, y, z}); })
        .def_static("scale", [](double x, double y, double z) { return api::Transform::scale({x, y, z}); })
        .def_static("rotate", [](std::array<double, 3> axis, double degrees) {
            return api::Transform::rotate(vec3(axis), degrees);
        }, py::arg("axis"), py::arg("degrees"))
        .def("__matmul__", [](const api::Transform& a, const api::Transform& b) { return a * b; })
        .def("matrix", &matrixOf);

    py::class_<PyScene>(m, "Scene", "A scene: Scene() builds one in code; load_scene() reads a scenefile.")
        .def(py::init<>())
        .def_readonly("warnings", &PyScene::warnings)
        .def("set_camera", [](PyScene& s, std::array<double, 3> position, std::array<double, 3> look,
                              std::array<double, 3> up, double heightAngle, double aperture, double focalLength) {
            s.scene.setCamera({vec3(position), vec3(look), vec3(up), heightAngle, aperture, focalLength});
        }, py::arg("position"), py::arg("look"), py::arg("up") = std::array<double, 3>{0, 1, 0},
           py::arg("height_angle") = 45.0, py::arg("aperture") = 0.0, py::arg("focal_length") = 0.0)
        .def_property_readonly("camera", [](const PyScene& s) {
            api::Camera c = s.scene.camera();
            py::dict d;
            d["position"] = tuple3(c.position);
            d["look"] = tuple3(c.look);
            d["up"] = tuple3(c.up);
            d["height_angle"] = c.heightAngleDegrees;
            return d;
        })
        .def("set_globals", [](PyScene& s, double ka, double kd, double ks, double kt) {
            s.scene.setGlobals({ka, kd, ks, kt});
        }, py::arg("ka") = 0.5, py::arg("kd") = 0.5, py::arg("ks") = 0.5, py::arg("kt") = 0.5)
        .def("add_light", [](PyScene& s, const std::string& type, std::array<double, 3> color,
                             std::array<double, 3> position, std::array<double, 3> direction,
                             std::array<double, 3> attenuation, double angle, double penumbra, double width,
                             double height) {
            api::Light light;
            light.type = lightType(type);
            light.color = vec3(color);
            light.position = vec3(position);
            light.direction = vec3(direction);
            light.attenuation = vec3(attenuation);
            light.angleDegrees = angle;
            light.penumbraDegrees = penumbra;
            light.width = width;
            light.height = height;
            s.scene.addLight(light);
        }, py::arg("type") = "point", py::arg("color") = std::array<double, 3>{1, 1, 1},
           py::arg("position") = std::array<double, 3>{3, 3, 3}, py::arg("direction") = std::array<double, 3>{0, 0, -1},
           py::arg("attenuation") = std::array<double, 3>{1, 0, 0}, py::arg("angle") = 45.0,
           py::arg("penumbra") = 0.0, py::arg("width") = 1.0, py::arg("height") = 1.0)
        .def("add_material", [](PyScene& s, std::array<double, 3> diffuse, std::array<double, 3> ambient,
                                std::array<double, 3> specular, std::array<double, 3> reflective,
                                std::array<double, 3> transparent, std::array<double, 3> emissive, double shininess,
                                double ior, int texture, double blend, std::array<double, 2> repeat, int bumpMap) {
            api::Material mat;
            mat.diffuse = vec3(diffuse);
            mat.ambient = vec3(ambient);
            mat.specular = vec3(specular);
            mat.reflective = vec3(reflective);
            mat.transparent = vec3(transparent);
            mat.emissive = vec3(emissive);
            mat.shininess = shininess;
            mat.ior = ior;
            mat.blend = blend;
            mat.texture = {texture, repeat[0], repeat[1]};
            mat.bumpMap = {bumpMap, repeat[0], repeat[1]};
            return s.scene.addMaterial(mat);
        }, py::arg("diffuse") = std::array<double, 3>{1, 1, 1}, py::arg("ambient") = std::array<double, 3>{0, 0, 0},
           py::arg("specular") = std::array<double, 3>{0, 0, 0}, py::arg("reflective") = std::array<double, 3>{0, 0, 0},
           py::arg("transparent") = std::array<double, 3>{0, 0, 0}, py::arg("emissive") = std::array<double, 3>{0, 0, 0},
           py::arg("shininess") = 0.0, py::arg("ior") = 1.0, py::arg("texture") = -1, py::arg("blend") = 0.0,
           py::arg("repeat") = std::array<double, 2>{1, 1}, py::arg("bump_map") = -1,
           "Returns the material's handle.")
        .def("add_texture", [](PyScene& s, const std::filesystem::path& file) {
            return s.scene.addTextureFromFile(file);
        }, py::arg("file"), "A texture from an image file; returns its handle.")
        .def("add_texture", [](PyScene& s, const py::array_t<float, py::array::c_style | py::array::forcecast>& rgb) {
            if (rgb.ndim() != 3 || rgb.shape(2) != 3) throw py::value_error("a texture array is H x W x 3, in [0, 1]");
            return s.scene.addTextureFromPixels(int(rgb.shape(1)), int(rgb.shape(0)),
                                                std::vector<float>(rgb.data(), rgb.data() + rgb.size()));
        }, py::arg("pixels"), "A texture from an H x W x 3 array in [0, 1], row 0 at the top; returns its handle.")
        .def("add_mesh", [](PyScene& s, const py::array_t<float, py::array::c_style | py::array::forcecast>& positions,
                            const py::array_t<uint32_t, py::array::c_style | py::array::forcecast>& triangles,
                            const py::array_t<float, py::array::c_style | py::array::forcecast>& normals,
                            const py::array_t<float, py::array::c_style | py::array::forcecast>& uvs) {
            return s.scene.addMesh(flat(positions, 3, "positions"), flat(triangles, 3, "triangles"),
                                   flat(normals, 3, "normals"), flat(uvs, 2, "uvs"));
        }, py::arg("positions"), py::arg("triangles"),
           py::arg("normals") = py::array_t<float>(), py::arg("uvs") = py::array_t<float>(),
           "A triangle mesh from N x 3 positions and M x 3 vertex indices; returns its handle.")
        .def("add_primitive", [](PyScene& s, const std::string& type, const api::Transform& transform, int material,
                                 int mesh) { s.scene.addPrimitive(shape(type), transform, material, mesh); },
             py::arg("shape"), py::arg("transform") = api::Transform(), py::arg("material") = 0, py::arg("mesh") = -1)
        .def_property_readonly("primitive_count", [](const PyScene& s) { return s.scene.primitiveCount(); });

    m.def("load_scene", [](const std::filesystem::path& file, std::vector<std::filesystem::path> searchPaths,
                           bool strict, bool textures) {
        api::LoadResult loaded = api::Scene::load(file, loadOptions(searchPaths, strict, textures));
        return PyScene{std::move(loaded.scene), std::move(loaded.warnings)};
    }, py::arg("file"), py::arg("search_paths") = std::vector<std::filesystem::path>{}, py::arg("strict") = false,
       py::arg("textures") = true, "Reads a scenefile; its warnings are in .warnings. Raises InputError.");
    m.def("scene_from_string", [](const std::string& xml, const std::filesystem::path& name,
                                  std::vector<std::filesystem::path> searchPaths, bool strict) {
        api::LoadResult loaded = api::Scene::fromString(xml, name, loadOptions(searchPaths, strict, true));
        return PyScene{std::move(loaded.scene), std::move(loaded.warnings)};
    }, py::arg("xml"), py::arg("name") = "scene.xml", py::arg("search_paths") = std::vector<std::filesystem::path>{},
       py::arg("strict") = false);

    m.def("list_devices", [] {
        py::list devices;
        for (const api::Device& d : api::listDevices()) {
            py::dict entry;
            entry["index"] = d.index;
            entry["name"] = d.name;
            entry["platform"] = d.platform;
            entry["gpu"] = d.gpu;
            entry["cpu"] = d.cpu;
            devices.append(entry);
        }
        return devices;
    }, "The OpenCL devices, numbered as device=<index> takes them.");

    py::class_<api::Renderer>(m, "Renderer", "Renders one scene on one device selection, frame after frame.")
        .def(py::init([](const PyScene& s, const std::string& device) {
            return std::make_unique<api::Renderer>(s.scene, device);
        }), py::arg("scene"), py::arg("device") = "auto")
        .def("set_camera", [](api::Renderer& r, std::array<double, 3> position, std::array<double, 3> look,
                              std::array<double, 3> up, double heightAngle) {
            api::Camera c = r.camera();
            c.position = vec3(position);
            c.look = vec3(look);
            c.up = vec3(up);
            c.heightAngleDegrees = heightAngle;
            r.setCamera(c);
        }, py::arg("position"), py::arg("look"), py::arg("up") = std::array<double, 3>{0, 1, 0},
           py::arg("height_angle") = 45.0)
        .def("set_options", [](api::Renderer& r, const py::kwargs& options) {
            r.setSettings(settingsFrom(options, r.settings()));
        }, "width, height, depth, aa, samples, seed, area_samples, shutter, threshold, shadows, reflections, "
           "refraction, textures, dof, dof_mode, fresnel, course_meshes, texture_filter")
        .def("render", [](api::Renderer& r, const std::string& dtype, const py::object& progress) {
            return renderArray(r, dtype, progress);
        }, py::arg("dtype") = "float32", py::arg("progress") = py::none(),
           "Renders a frame: an H x W x 3 array. progress(fraction) is called now and then.");

    m.def("render", [](const PyScene& s, const std::string& device, const std::string& dtype,
                       const py::object& progress, const py::kwargs& options) {
        api::Renderer renderer(s.scene, device);
        renderer.setSettings(settingsFrom(options, renderer.settings()));
        return renderArray(renderer, dtype, progress);
    }, py::arg("scene"), py::arg("device") = "auto", py::arg("dtype") = "float32", py::arg("progress") = py::none(),
       "Renders the scene once: an H x W x 3 array (float32 linear, or uint8 as ray's PNGs). Options as "
       "Renderer.set_options.");

    m.def("save_image", [](const py::array_t<float, py::array::c_style | py::array::forcecast>& rgb,
                           const std::filesystem::path& file) {
        if (rgb.ndim() != 3 || rgb.shape(2) != 3) throw py::value_error("an image is an H x W x 3 float array");
        api::saveImage(std::vector<float>(rgb.data(), rgb.data() + rgb.size()), int(rgb.shape(1)),
                       int(rgb.shape(0)), file);
    }, py::arg("image"), py::arg("file"), "Writes a float H x W x 3 image; the extension picks the format.");
}
