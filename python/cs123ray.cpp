// cs123ray: ray's public API (include/ray/) as a Python module, through pybind11.
//
// Named cs123ray, not ray: `import ray` is the widely installed distributed-computing
// package on PyPI, and the course's scenefile format (CS123) names what this one renders.
#include <pybind11/functional.h>
#include <pybind11/eval.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <future>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>

#include "ray/ray.h"

namespace py = pybind11;
using namespace pybind11::literals;  // "name"_a
namespace api = ray::api;

// python/notebook.py, embedded at build time (python/CMakeLists.txt): run in the module's
// namespace at import.
extern const char* const kNotebookPython;

namespace {

// cs123ray.RenderedImage (python/notebook.py), the ndarray subclass renders are returned as.
// Never destroyed: Python may be gone when static objects are.
py::object& renderedImageType() {
    static py::object* type = new py::object();
    return *type;
}

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

// An N x columns array (or nested sequences) of numbers, row by row; None or empty: none.
template <class T>
std::vector<T> flat(const py::object& values, py::ssize_t columns, const char* what) {
    if (values.is_none()) return {};
    auto array = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(values);
    if (!array) {
        PyErr_Clear();
        throw py::type_error(std::string(what) + " must be an N x " + std::to_string(columns) +
                             " array of numbers, not " + std::string(py::str(values.get_type().attr("__name__"))));
    }
    if (array.size() == 0) return {};
    if (array.ndim() != 2 || array.shape(1) != columns)
        throw py::value_error(std::string(what) + " must be an N x " + std::to_string(columns) +
                              " array, not one of shape " + std::string(py::str(array.attr("shape"))));
    return std::vector<T>(array.data(), array.data() + array.size());
}

// M x 3 vertex indices: integers (a float index is a mistake, not something to round),
// none negative.
std::vector<uint32_t> vertexIndices(const py::object& triangles) {
    auto array = py::array::ensure(triangles);
    if (!array) {
        PyErr_Clear();
        throw py::type_error("triangles must be an M x 3 array of vertex indices");
    }
    const char kind = array.dtype().kind();
    if (array.size() > 0 && kind != 'i' && kind != 'u')
        throw py::type_error("triangles must hold integer vertex indices, not " + std::string(py::str(array.dtype())));
    std::vector<int64_t> indices = flat<int64_t>(array, 3, "triangles");
    for (int64_t index : indices)
        if (index < 0 || index > int64_t(std::numeric_limits<uint32_t>::max()))
            throw py::value_error("triangles hold vertex index " + std::to_string(index) +
                                  "; indices count vertices from 0");
    return std::vector<uint32_t>(indices.begin(), indices.end());
}

// ---------------------------------------------------------------------------------------
// Render options: each value's type checked as Python's own functions check theirs (a
// TypeError naming the option and what it takes), its range by the C++ API (a ValueError).

bool isBool(const py::handle& value) {
    return PyBool_Check(value.ptr()) || py::isinstance(value, py::module_::import("numpy").attr("bool_"));
}

// A value as a message quotes it: its repr, cut short (a string of 10^5 characters is named,
// not echoed).
std::string shortRepr(const py::handle& value) {
    const std::string text = py::repr(value);
    return text.size() <= 80 ? text : text.substr(0, 60) + "... (" + std::to_string(text.size()) + " characters)";
}

[[noreturn]] void wrongType(const std::string& name, const char* expected, const py::handle& value) {
    throw py::type_error(name + " must be " + expected + ", not " + std::string(py::str(value.get_type().attr("__name__"))) +
                         " (" + shortRepr(value) + ")");
}

// An int, a NumPy integer, anything with __index__; not a bool, not a float (3.5 pixels).
long long integerOption(const std::string& name, const py::handle& value) {
    if (isBool(value) || !PyIndex_Check(value.ptr())) wrongType(name, "an integer", value);
    py::int_ integer = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
    if (!integer) throw py::error_already_set();
    int overflow = 0;
    const long long result = PyLong_AsLongLongAndOverflow(integer.ptr(), &overflow);
    if (overflow != 0) throw py::value_error(name + " " + shortRepr(value) + " is out of range");
    return result;
}

double realOption(const std::string& name, const py::handle& value) {
    const bool number = PyFloat_Check(value.ptr()) || PyIndex_Check(value.ptr()) || py::hasattr(value, "__float__");
    if (isBool(value) || PyUnicode_Check(value.ptr()) || PyBytes_Check(value.ptr()) || !number)
        wrongType(name, "a number", value);
    return py::float_(py::reinterpret_borrow<py::object>(value));
}

// N numbers (a color, a point, a direction, a pair of repeats): a sequence of N real numbers,
// a NumPy array included. A string, a wrong count or a non-number is a TypeError naming the
// argument; whether each number is finite and in range is the C++ API's check (InputError).
template <size_t N>
std::array<double, N> numbersArg(const std::string& name, const py::handle& value) {
    static const std::string kExpected = "a sequence of " + std::to_string(N) + " numbers";
    if (PyUnicode_Check(value.ptr()) || PyBytes_Check(value.ptr()) || !PySequence_Check(value.ptr()))
        wrongType(name, kExpected.c_str(), value);
    const auto items = py::reinterpret_borrow<py::sequence>(value);
    if (items.size() != N)
        throw py::type_error(name + " must be " + kExpected + ", not " + std::to_string(items.size()) + ": " +
                             shortRepr(value));
    std::array<double, N> numbers{};
    for (size_t i = 0; i < N; ++i) numbers[i] = realOption(name + "[" + std::to_string(i) + "]", items[i]);
    return numbers;
}

api::Vec3 vec3Arg(const std::string& name, const py::handle& value) { return vec3(numbersArg<3>(name, value)); }

// A handle (a texture's, a mesh's): an integer that fits an int.
int handleArg(const std::string& name, const py::handle& value) {
    const long long number = integerOption(name, value);
    if (number < std::numeric_limits<int>::min() || number > std::numeric_limits<int>::max())
        throw py::value_error(name + " " + std::to_string(number) + " is out of range");
    return int(number);
}

bool boolOption(const std::string& name, const py::handle& value) {
    if (!isBool(value)) wrongType(name, "True or False", value);
    return PyObject_IsTrue(value.ptr()) == 1;
}

std::string textOption(const std::string& name, const py::handle& value) {
    if (!PyUnicode_Check(value.ptr())) wrongType(name, "a string", value);
    return py::str(value);
}

// The render options: the settings the C++ API describes (ray's settings table), each
// value's type checked here as Python checks its own, its range and choice by the API.
const std::vector<api::SettingDescription>& renderOptions() {
    static const std::vector<api::SettingDescription> options = api::describeSettings();
    return options;
}

std::string optionNames() {
    std::string names;
    for (const api::SettingDescription& option : renderOptions()) names += (names.empty() ? "" : ", ") + option.name;
    return names;
}

[[noreturn]] void unknownOption(const std::string& name) {
    py::list known;
    for (const api::SettingDescription& option : renderOptions()) known.append(option.name);
    py::list close = py::module_::import("difflib").attr("get_close_matches")(name, known, 1);
    std::string hint = close.empty() ? "" : "; did you mean '" + std::string(py::str(close[0])) + "'?";
    throw py::type_error("unknown render option '" + name + "'" + hint + " (the options are " + optionNames() + ")");
}

api::SettingValue optionValue(const api::SettingDescription& option, const py::handle& value) {
    using Kind = api::SettingDescription::Kind;
    switch (option.kind) {
        case Kind::Integer: return int64_t(integerOption(option.name, value));
        case Kind::Number: return realOption(option.name, value);
        case Kind::Switch: return boolOption(option.name, value);
        case Kind::Choice: return textOption(option.name, value);
    }
    unknownOption(option.name);
}

const api::SettingDescription* findOption(const std::string& name) {
    for (const api::SettingDescription& option : renderOptions())
        if (name == option.name) return &option;
    return nullptr;
}

void setOption(api::Settings& s, const std::string& name, const py::handle& value) {
    const api::SettingDescription* option = findOption(name);
    if (!option) unknownOption(name);
    api::setSetting(s, name, optionValue(*option, value));
}

// The options over `s`. Width and height come together: one alone would keep the other
// (1024 x 768 by default), a stretched image nobody asked for.
api::Settings settingsFrom(const py::kwargs& options, api::Settings s) {
    if (options.contains("width") != options.contains("height"))
        throw py::value_error(std::string(options.contains("width") ? "width" : "height") +
                              " without " + (options.contains("width") ? "height" : "width") +
                              ": give both (the image is " + std::to_string(s.width) + " x " +
                              std::to_string(s.height) + " otherwise)");
    for (const auto& [key, value] : options) setOption(s, py::str(key), value);
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

// The dtype asked for, as NumPy users write it ("uint8", np.uint8, np.dtype("float32")).
std::string dtypeName(const py::object& dtype) {
    const std::string name = py::str(py::dtype::from_args(dtype).attr("name"));
    if (name != "float32" && name != "uint8") throw py::value_error("dtype must be float32 or uint8, not " + name);
    return name;
}

// Renders a frame as an H x W x 3 array: float32 (linear, unclamped) or uint8 (the bytes
// ray's 8-bit images hold).
// stats: the frame's statistics, if wanted.
py::array renderArray(api::Renderer& renderer, const py::object& dtype, const py::object& progress,
                      api::FrameStats* stats = nullptr) {
    const std::string name = dtypeName(dtype);
    const api::Settings& s = renderer.settings();
    py::array_t<float> rgb({py::ssize_t(s.height), py::ssize_t(s.width), py::ssize_t(3)});
    api::FrameStats frame = renderWatched(renderer, rgb.mutable_data(), size_t(rgb.size()), progress);
    if (stats) *stats = frame;
    py::array image = rgb;
    if (name == "uint8") {
        py::array_t<uint8_t> bytes({py::ssize_t(s.height), py::ssize_t(s.width), py::ssize_t(3)});
        std::transform(rgb.data(), rgb.data() + rgb.size(), bytes.mutable_data(), api::toByte);
        image = bytes;
    }
    // A view of the same pixels as a RenderedImage, which shows itself in a notebook.
    return py::reinterpret_borrow<py::array>(image.attr("view")(renderedImageType()));
}

// ---------------------------------------------------------------------------------------
// Images and textures from NumPy: floats are linear (1.0 is full), uint8 are ray's bytes
// (255 is full), as render(dtype=...) makes them; other dtypes have no agreed scale.

bool isBytes(const py::array& image) { return image.dtype().kind() == 'u' && image.dtype().itemsize() == 1; }
bool isFloats(const py::array& image) { return image.dtype().kind() == 'f'; }

// An H x W x 3 array of floats or bytes; `what` names it in messages.
void checkImageArray(const py::array& image, const char* what) {
    if (!isBytes(image) && !isFloats(image))
        throw py::type_error(std::string(what) + " must hold floats (1.0 is full) or uint8 (255 is full), not " +
                             std::string(py::str(image.dtype())) + "; convert it with .astype(numpy.uint8) (values 0 to 255) or .astype(numpy.float32) / 255");
    if (image.ndim() != 3 || image.shape(2) != 3)
        throw py::value_error(std::string(what) + " must be an H x W x 3 array (RGB), not one of shape " +
                              std::string(py::str(image.attr("shape"))));
}

template <class T>
std::vector<T> valuesOf(const py::array& image) {
    auto contiguous = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(image);
    if (!contiguous) {  // ensure() cleared the error it met; pybind11 would say "Internal error"
        PyErr_Clear();
        throw py::type_error("the image's values cannot be read as numbers (" +
                             std::string(py::str(image.dtype())) + "); give a float or uint8 array");
    }
    return std::vector<T>(contiguous.data(), contiguous.data() + contiguous.size());
}

// Linear floats: as they are, or 8-bit v as v / 255 (how the loader reads 8-bit textures).
std::vector<float> linearPixels(const py::array& image) {
    if (isFloats(image)) return valuesOf<float>(image);
    std::vector<uint8_t> bytes = valuesOf<uint8_t>(image);
    std::vector<float> rgb(bytes.size());
    std::transform(bytes.begin(), bytes.end(), rgb.begin(), [](uint8_t v) { return float(v) / 255.0f; });
    return rgb;
}

// The pixel budget of an image array, checked before its values are copied (the copy of a
// 50,000 x 100,000 array took 15 GB before MemoryError): a texture gets a texture file's
// budget, an image to save a render's largest. InputError, as for a file.
void checkArrayPixels(const py::array& image, const char* what, uint64_t maxPixels, int64_t maxSide,
                      const std::string& budget) {
    const int64_t height = image.shape(0), width = image.shape(1);
    if (width > 0 && height > 0 && width <= maxSide && height <= maxSide && uint64_t(width) * uint64_t(height) <= maxPixels)
        return;
    throw api::InputError("error: " + std::string(what) + " of " + std::to_string(width) + " x " +
                              std::to_string(height) + " pixels is " + (width > 0 && height > 0 ? "more than " + budget + "; scale it down" : "empty"),
                          "", 0);
}

void saveArray(const py::array& image, const std::filesystem::path& file, bool replaceReadOnly) {
    checkImageArray(image, "an image");
    checkArrayPixels(image, "an image", uint64_t(api::kMaxImageSide) * api::kMaxImageSide, api::kMaxImageSide,
                     "the largest image ray renders, " + std::to_string(api::kMaxImageSide) + " a side");
    const int width = int(image.shape(1)), height = int(image.shape(0));
    const api::WriteOptions options{replaceReadOnly};
    if (isBytes(image)) api::saveImage(valuesOf<uint8_t>(image), width, height, file, options);
    else api::saveImage(valuesOf<float>(image), width, height, file, options);
}

// Text from C++ as Python's str: messages and warnings hold file names, which need not be
// UTF-8 (a folder named in Latin-1); their stray bytes become \xNN escapes rather than a
// UnicodeDecodeError in place of the error that was meant.
py::str textOf(const std::string& text) {
    return py::reinterpret_steal<py::str>(PyUnicode_DecodeUTF8(text.data(), py::ssize_t(text.size()), "backslashreplace"));
}

// A file name from C++ as os.fsdecode gives it: os.fsencode of it is the file's bytes.
py::object fileNameOf(const std::string& name) {
    return py::reinterpret_steal<py::object>(PyUnicode_DecodeFSDefaultAndSize(name.data(), py::ssize_t(name.size())));
}

// The message without the C++ API's "error: " where it names no file: Python prints the
// exception's type before it ("InputError: width must be ...").
std::string plainMessage(const api::InputError& e) {
    const std::string message = e.what();
    const std::string prefix = "error: ";
    return e.file().empty() && message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message;
}

// cs123ray.Error (a RuntimeError); InputError, also a ValueError, since a bad value is what
// it reports (a scene's, an argument's), with .file and .line; DeviceError.
void registerErrors(py::module_& m) {
    static py::exception<api::Error> error(m, "Error", PyExc_RuntimeError);
    static py::exception<api::InputError> inputError(m, "InputError", py::make_tuple(error, py::handle(PyExc_ValueError)));
    static py::exception<api::DeviceError> deviceError(m, "DeviceError", error.ptr());
    error.doc() = "The base of cs123ray's errors.";
    inputError.doc() = "Bad input: a scene that does not parse, a value out of range. .file and .line give the "
                       "place ('' and 0 where there is none).";
    deviceError.doc() = "The device failed: no OpenCL platform, a kernel that does not build, an unwritable file.";
    py::register_exception_translator([](std::exception_ptr thrown) {
        try {
            if (thrown) std::rethrow_exception(thrown);
        } catch (const api::InputError& e) {
            py::object instance = py::reinterpret_borrow<py::object>(inputError.ptr())(textOf(plainMessage(e)));
            instance.attr("file") = fileNameOf(e.file());
            instance.attr("line") = e.line();
            PyErr_SetObject(inputError.ptr(), instance.ptr());
        } catch (const api::DeviceError& e) {
            PyErr_SetObject(deviceError.ptr(), textOf(e.what()).ptr());
        } catch (const api::Error& e) {
            PyErr_SetObject(error.ptr(), textOf(e.what()).ptr());
        }
    });
}

// Without NumPy every array argument fails, and pybind11 would say only "initialization
// failed": say what is missing and how to get it instead.
void requireNumpy() {
    try {
        py::module_::import("numpy");
    } catch (py::error_already_set& e) {
        const std::string python = py::str(py::module_::import("sys").attr("executable"));
        throw py::import_error("cs123ray needs NumPy, which " + python + " cannot import (" + e.what() +
                               "); install it: apt-get install python3-numpy (Debian's /usr/bin/python3), "
                               "or python3 -m pip install numpy");
    }
}

std::string vecText(const api::Vec3& v) {
    std::ostringstream out;
    out << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return out.str();
}

std::string transformRepr(const api::Transform& t) {
    std::ostringstream out;
    out << "Transform([";
    for (int r = 0; r < 3; ++r)
        out << (r ? ", " : "") << "[" << t.m[r][0] << ", " << t.m[r][1] << ", " << t.m[r][2] << ", " << t.m[r][3]
            << "]";
    out << ", [0, 0, 0, 1]])";
    return out.str();
}

std::string sceneRepr(const PyScene& s) {
    const api::Camera camera = s.scene.camera();
    return "<cs123ray.Scene: " + std::to_string(s.scene.primitiveCount()) +
           (s.scene.primitiveCount() == 1 ? " primitive, " : " primitives, ") +
           std::to_string(s.scene.lightCount()) + (s.scene.lightCount() == 1 ? " light" : " lights") + ", camera at " + vecText(camera.position) + " looking " +
           vecText(camera.look) + ">";
}

std::string rendererRepr(const api::Renderer& r) {
    const api::Settings& s = r.settings();
    const std::vector<std::string>& antialiasNames = findOption("aa")->choices;  // in the enum's order
    return "<cs123ray.Renderer device='" + r.devices() + "', " + std::to_string(s.width) + " x " +
           std::to_string(s.height) + ", depth " + std::to_string(s.depth) + ", aa='" + antialiasNames.at(int(s.antialias)) +
           "'>";
}

// ---------------------------------------------------------------------------------------
// The module: every function takes keywords, named as the scenefile names what they set.

using Triple = std::array<double, 3>;

void bindTransform(py::module_& m) {
    py::class_<api::Transform>(m, "Transform",
                               "An object-to-world affine transform. a @ b applies b first, as nested transblocks do.")
        .def(py::init<>(), "The identity.")
        .def(py::init(&transformFrom), py::arg("matrix"),
             "From a 3x4 or 4x4 row-major matrix (nested sequences or a NumPy array).")
        .def_static("translate", [](const py::handle& x, const py::handle& y, const py::handle& z) {
            return api::Transform::translate({realOption("x", x), realOption("y", y), realOption("z", z)});
        },
                    py::arg("x"), py::arg("y"), py::arg("z"), "A translation by (x, y, z).")
        .def_static("scale", [](const py::handle& x, const py::handle& y, const py::handle& z) {
            return api::Transform::scale({realOption("x", x), realOption("y", y), realOption("z", z)});
        },
                    py::arg("x"), py::arg("y"), py::arg("z"), "A scaling by x, y and z along the axes.")
        .def_static("rotate", [](const py::handle& axis, const py::handle& degrees) {
            return api::Transform::rotate(vec3Arg("axis", axis), realOption("degrees", degrees));
        },
                    py::arg("axis"), py::arg("degrees"),
                    "A rotation by `degrees` about `axis` (x, y, z), counter-clockwise looking down the axis.")
        .def("__matmul__", [](const api::Transform& a, const api::Transform& b) { return a * b; }, py::arg("other"),
             "self @ other: other applies first.")
        .def("matrix", &matrixOf, "The 4x4 row-major matrix, a NumPy array.")
        .def("__repr__", &transformRepr);
}

// ---------------------------------------------------------------------------------------
// The scene as its file has it: objects, their edits, lights, saving

const char* shapeName(api::Shape shape) {
    static const char* const kNames[] = {"cube", "sphere", "cylinder", "cone", "torus", "mesh"};
    return kNames[int(shape)];
}

const char* lightTypeName(api::LightType type) {
    static const char* const kNames[] = {"point", "directional", "spot", "area"};
    return kNames[int(type)];
}

// A color or a point as a Python tuple.
py::tuple pyTuple(const api::Vec3& v) { return py::make_tuple(v.x, v.y, v.z); }

py::dict materialDict(const api::Material& m) {
    py::dict d;
    d["diffuse"] = pyTuple(m.diffuse);
    d["ambient"] = pyTuple(m.ambient);
    d["specular"] = pyTuple(m.specular);
    d["reflective"] = pyTuple(m.reflective);
    d["transparent"] = pyTuple(m.transparent);
    d["emissive"] = pyTuple(m.emissive);
    d["shininess"] = m.shininess;
    d["ior"] = m.ior;
    d["blend"] = m.blend;
    d["texture"] = m.texture.texture;
    d["repeat"] = py::make_tuple(m.texture.repeatU, m.texture.repeatV);
    d["bump_map"] = m.bumpMap.texture;
    return d;
}

py::dict lightDict(const api::Light& l) {
    py::dict d;
    d["type"] = lightTypeName(l.type);
    d["color"] = pyTuple(l.color);
    d["position"] = pyTuple(l.position);
    d["direction"] = pyTuple(l.direction);
    d["attenuation"] = pyTuple(l.attenuation);
    d["angle"] = l.angleDegrees;
    d["penumbra"] = l.penumbraDegrees;
    d["width"] = l.width;
    d["height"] = l.height;
    return d;
}

// ---------------------------------------------------------------------------------------
// The one edit model (docs/modeler-protocol.md): keywords are the field table's (a field's
// scenefile name, "texture.u" as texture_u), read from api::editableFields(); values are
// checked for their type here (a TypeError naming the keyword), for their range by the
// C++ API (InputError, a ValueError).

const std::vector<api::FieldInfo>& fieldTable() {
    static const std::vector<api::FieldInfo> table = api::editableFields();
    return table;
}

// The owner of a node id's fields: "object-3" -> "object", "block-2" -> "transblock".
std::string ownerOf(const std::string& node) {
    const std::string kind = node.substr(0, node.find('-'));
    return kind == "block" ? "transblock" : kind;
}

// The field of `owner` a keyword names; a ValueError listing the owner's keywords otherwise.
const api::FieldInfo& fieldNamed(const std::string& owner, const std::string& keyword) {
    std::string known;
    for (const api::FieldInfo& field : fieldTable()) {
        if (field.owner != owner) continue;
        if (field.keyword == keyword || field.name == keyword) return field;
        known += (known.empty() ? "" : ", ") + field.keyword;
    }
    if (known.empty()) throw py::value_error("a " + owner + " has no fields to set");
    py::list keywords;
    for (const api::FieldInfo& field : fieldTable())
        if (field.owner == owner) keywords.append(field.keyword);
    py::list close = py::module_::import("difflib").attr("get_close_matches")(keyword, keywords, 1);
    const std::string hint = close.empty() ? "" : "; did you mean '" + std::string(py::str(close[0])) + "'?";
    const std::string article = std::string("aeiou").find(owner[0]) != std::string::npos ? "an " : "a ";
    throw py::value_error(article + owner + " has no field " + shortRepr(py::str(keyword)) + hint +
                          " (its fields: " + known + ")");
}

std::vector<api::TransformStep> transformSteps(const std::string& name, const py::handle& value) {
    if (PyUnicode_Check(value.ptr()) || !PySequence_Check(value.ptr()))
        wrongType(name, "a list of (kind, numbers) steps", value);
    std::vector<api::TransformStep> steps;
    for (const py::handle& item : py::reinterpret_borrow<py::sequence>(value)) {
        if (PyUnicode_Check(item.ptr()) || !PySequence_Check(item.ptr()) || py::len(item) != 2)
            wrongType(name, "a list of (kind, numbers) steps, such as ('translate', (0, 1, 0))", item);
        const auto pair = py::reinterpret_borrow<py::sequence>(item);
        const std::string kind = textOption(name + "'s kind", pair[0]);
        api::TransformStep step;
        if (kind == "translate") step.kind = api::TransformStep::Kind::Translate;
        else if (kind == "rotate") step.kind = api::TransformStep::Kind::Rotate;
        else if (kind == "scale") step.kind = api::TransformStep::Kind::Scale;
        else if (kind == "matrix") step.kind = api::TransformStep::Kind::Matrix;
        else throw py::value_error(name + ": a step is translate, rotate, scale or matrix, not '" + shortRepr(pair[0]) + "'");
        if (PyUnicode_Check(pair[1].ptr()) || !PySequence_Check(pair[1].ptr())) wrongType(name, "numbers", pair[1]);
        for (const py::handle& number : py::reinterpret_borrow<py::sequence>(pair[1]))
            step.values.push_back(realOption(name, number));
        steps.push_back(std::move(step));
    }
    return steps;
}

api::FieldValue fieldValue(const api::FieldInfo& field, const std::string& keyword, const py::handle& value) {
    if (field.kind == "number") return realOption(keyword, value);
    if (field.kind == "color" || field.kind == "vector") return vec3Arg(keyword, value);
    if (field.kind == "choice" || field.kind == "text" || field.kind == "file") return textOption(keyword, value);
    if (field.kind == "matrix") {
        if (!py::isinstance<api::Transform>(value)) wrongType(keyword, "a Transform", value);
        return value.cast<api::Transform>();
    }
    return transformSteps(keyword, value);
}

api::FieldValues fieldValues(const std::string& owner, const py::kwargs& fields) {
    api::FieldValues values;
    for (const auto& [key, value] : fields) {
        const std::string keyword = py::str(key);
        values.emplace_back(std::string(fieldNamed(owner, keyword).name), fieldValue(fieldNamed(owner, keyword), keyword, value));
    }
    return values;
}

py::object fieldPython(const api::FieldValue& value) {
    return std::visit(
        [](const auto& v) -> py::object {
            using V = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<V, api::Vec3>) return pyTuple(v);
            else if constexpr (std::is_same_v<V, std::vector<api::TransformStep>>) {
                static const char* const kKinds[] = {"translate", "rotate", "scale", "matrix"};
                py::list steps;
                for (const api::TransformStep& step : v)
                    steps.append(py::make_tuple(kKinds[int(step.kind)], py::tuple(py::cast(step.values))));
                return steps;
            } else return py::cast(v);
        },
        value);
}

py::dict resultDict(const api::EditResult& result) {
    py::dict d;
    d["changed"] = result.changed;
    d["added"] = result.added;
    d["removed"] = result.removed;
    return d;
}

// A node id from Python: a string ("object-3") or a SceneObject handle.
std::string nodeArg(const std::string& name, const py::handle& value);

std::vector<std::string> nodeArgs(const py::args& nodes) {
    std::vector<std::string> ids;
    for (const py::handle& node : nodes) ids.push_back(nodeArg("node", node));
    if (ids.empty()) throw py::type_error("name at least one node (an id such as 'object-3', or a SceneObject)");
    return ids;
}

// A handle on one object of a scene: the scene (kept alive by `owner`, the Python object
// holding it) and the object's stable id. Every use asks the scene, so a handle whose
// object was removed raises InputError (a ValueError).
struct PyObjectHandle {
    py::object owner;
    api::Scene* scene = nullptr;
    int id = -1;

    api::SceneObject get() const { return scene->object(id); }
};

std::string nodeArg(const std::string& name, const py::handle& value) {
    if (py::isinstance<PyObjectHandle>(value)) return "object-" + std::to_string(value.cast<const PyObjectHandle&>().id);
    return textOption(name, value);
}

// The handles of every object of `scene`, held by `owner` (a Scene, or a Renderer whose
// scene it is).
py::list objectHandles(const py::object& owner, api::Scene& scene) {
    py::list handles;
    for (const api::SceneObject& object : scene.objects()) handles.append(PyObjectHandle{owner, &scene, object.id});
    return handles;
}

std::string objectRepr(const PyObjectHandle& h) {
    try {
        const api::SceneObject o = h.get();
        return "<cs123ray.SceneObject " + std::to_string(o.id) + ": " + shapeName(o.shape) + " at " + o.path +
               (o.instances == 1 ? "" : ", " + std::to_string(o.instances) + " instances") + ">";
    } catch (const api::InputError&) {
        return "<cs123ray.SceneObject " + std::to_string(h.id) + ": removed>";
    }
}

void bindSceneObject(py::module_& m) {
    py::class_<PyObjectHandle>(m, "SceneObject",
                               "One object of a scene (an <object type=\"primitive\"> of its file, or one placed with "
                               "add_primitive), from Scene.objects. An object inside a master is one object: editing "
                               "it edits every instance. Once removed, every use raises InputError (a ValueError).")
        .def_property_readonly("id", [](const PyObjectHandle& h) { return h.id; },
                               "Its stable id (never reused in its scene).")
        .def_property_readonly("path", [](const PyObjectHandle& h) { return h.get().path; },
                               "Its place in the scenefile's tree: 'root/transblock[1]/object[0]', or in a master "
                               "the master's name first ('leg/transblock[0]/object[0]').")
        .def_property_readonly("shape", [](const PyObjectHandle& h) { return shapeName(h.get().shape); },
                               "'cube', 'sphere', 'cylinder', 'cone', 'torus' or 'mesh'.")
        .def_property_readonly("material", [](const PyObjectHandle& h) { return materialDict(h.get().material); },
                               "Its material, as a dict of add_material's arguments.")
        .def_property("transform", [](const PyObjectHandle& h) { return h.get().objectToWorld; },
                      [](const PyObjectHandle& h, const api::Transform& t) { h.scene->setObjectToWorld(h.id, t); },
                      "Object to world of its first instance (a Transform); setting it is set_transform.")
        .def_property_readonly("in_master", [](const PyObjectHandle& h) { return h.get().inMaster; },
                               "Whether it is in a master (a tree other than 'root').")
        .def_property_readonly("instances", [](const PyObjectHandle& h) { return h.get().instances; },
                               "How many instances of it are rendered.")
        .def("set_material", [](const PyObjectHandle& h, const py::kwargs& fields) {
            for (const auto& [key, value] : fields) {
                const api::FieldInfo& field = fieldNamed("object", py::str(key));
                if (field.group != "material" && field.group != "texture" && field.group != "bump map")
                    throw py::value_error("set_material sets a material, a texture or a bump map, not " + field.name +
                                          " (Scene.set sets any field)");
            }
            return resultDict(h.scene->set("object-" + std::to_string(h.id), fieldValues("object", fields)));
        }, "Changes the fields given (the field table's keywords, cs123ray.fields(): diffuse=(r, g, b), "
           "shininess=..., texture='wood.png', texture_u=2, ...), keeping the others; in every instance. Values the "
           "loader refuses raise InputError (a ValueError), values of the wrong type TypeError, and change nothing.")
        .def("set_transform", [](const PyObjectHandle& h, const api::Transform& t) { h.scene->setObjectToWorld(h.id, t); },
             py::arg("transform"),
             "Places the object so that its first instance's object-to-world is `transform` (other instances, "
             "through masters, keep their place relative to it). A singular transform raises InputError.")
        .def("remove", [](const PyObjectHandle& h) { h.scene->removeObject(h.id); },
             "Removes the object from its scene (from its master: from every instance).")
        .def("__eq__", [](const PyObjectHandle& a, const PyObjectHandle& b) { return a.scene == b.scene && a.id == b.id; })
        .def("__hash__", [](const PyObjectHandle& h) { return py::hash(py::make_tuple(size_t(h.scene), h.id)); })
        .def("__repr__", &objectRepr);
}

// A Renderer and the scene it renders, which Python sees as renderer.scene: a Scene object
// of its own (a copy of the one it was made with), shared with the C++ renderer, so that
// edits through it are what the next frame renders.
struct PyRenderer {
    std::shared_ptr<PyScene> scene;
    std::unique_ptr<api::Renderer> renderer;
    std::optional<api::FrameStats> stats;  // the last frame's
};

// The last frame's statistics (renderer.stats); empty before the first frame.
py::dict statsDict(const std::optional<api::FrameStats>& stats) {
    py::dict d;
    if (!stats) return d;
    d["device"] = stats->device;
    d["primary_rays"] = stats->primaryRays;
    d["shadow_rays"] = stats->shadowRays;
    d["secondary_rays"] = stats->secondaryRays;
    d["pack_seconds"] = stats->packSeconds;
    d["bvh_build_seconds"] = stats->bvhBuildSeconds;
    d["upload_seconds"] = stats->uploadSeconds;
    d["kernel_build_seconds"] = stats->kernelBuildSeconds;
    d["render_seconds"] = stats->renderSeconds;
    d["cancelled"] = stats->cancelled;
    d["scene_update"] = py::dict("packing"_a = stats->sceneUpdate.packing, "bvh"_a = stats->sceneUpdate.bvh,
                                 "tables"_a = stats->sceneUpdate.tables);
    return d;
}

// What renderer.pick gives Python: the hit, and the scene's object as a SceneObject handle.
struct PyPick {
    api::Pick hit;
    py::object object;  // a PyObjectHandle, or None
    std::string path;
};

std::string pickRepr(const api::Pick& p, const std::string& path) {
    char text[160];
    std::snprintf(text, sizeof text, " at (%.4g, %.4g, %.4g), distance %.4g>", p.point.x, p.point.y, p.point.z,
                  p.distance);
    return "<cs123ray.Pick object " + std::to_string(p.object) + " (" + path + "), instance " +
           std::to_string(p.instance) + text;
}

void bindScene(py::class_<PyScene, std::shared_ptr<PyScene>>& scene) {
    scene.def(py::init<>(), "An empty scene: the default camera, no lights, no primitives.")
        .def_property_readonly("warnings", [](const PyScene& s) {
            py::list warnings;
            for (const std::string& warning : s.warnings) warnings.append(textOf(warning));
            return warnings;
        }, "The loader's warnings, complete ('scene.xml:7: warning: ...').")
        .def("set_camera", [](PyScene& s, const py::handle& position, const py::handle& look, const py::handle& up,
                              const py::handle& heightAngle, const py::handle& aperture, const py::handle& focalLength) {
            s.scene.setCamera({vec3Arg("position", position), vec3Arg("look", look), vec3Arg("up", up),
                               realOption("height_angle", heightAngle), realOption("aperture", aperture),
                               realOption("focal_length", focalLength)});
        }, py::arg("position"), py::arg("look"), py::arg("up") = Triple{0, 1, 0}, py::arg("height_angle") = 45.0,
           py::arg("aperture") = 0.0, py::arg("focal_length") = 0.0,
           "The camera: its position, the direction it looks, its up vector, the full vertical field of view in "
           "degrees, and a thin lens (aperture diameter and focal length; 0 is a pinhole).")
        .def_property_readonly("camera", [](const PyScene& s) {
            api::Camera c = s.scene.camera();
            py::dict d;
            d["position"] = tuple3(c.position);
            d["look"] = tuple3(c.look);
            d["up"] = tuple3(c.up);
            d["height_angle"] = c.heightAngleDegrees;
            d["aperture"] = c.aperture;
            d["focal_length"] = c.focalLength;
            return d;
        }, "The camera, as a dict of set_camera's arguments.")
        .def("set_globals", [](PyScene& s, const py::handle& ka, const py::handle& kd, const py::handle& ks,
                               const py::handle& kt) {
            s.scene.setGlobals({realOption("ka", ka), realOption("kd", kd), realOption("ks", ks), realOption("kt", kt)});
        }, py::arg("ka") = 0.5, py::arg("kd") = 0.5, py::arg("ks") = 0.5, py::arg("kt") = 0.5,
           "The global coefficients of <globaldata>: ambient, diffuse, specular (and reflection), transparency.")
        .def("add_light", [](PyScene& s, const py::handle& type, const py::kwargs& fields) {
            py::kwargs renamed;
            for (const auto& [key, value] : fields)  // add_light's keyword before the table's: attenuation
                renamed[py::str(key).equal(py::str("attenuation")) ? py::str("function") : py::str(key)] = value;
            return resultDict(s.scene.addLight(textOption("type", type), fieldValues("light", renamed)));
        }, py::arg("type") = "point",
           "A light: type 'point', 'directional', 'spot' or 'area', with the fields given (the field table's "
           "keywords, cs123ray.fields(): color, position, direction, function (attenuation, as it was called: c1, "
           "c2, c3 of 1/(c1 + c2 d + c3 d^2)), a spot's angle and penumbra in degrees, an area light's width and "
           "height). Values the scenefile loader refuses raise InputError (a ValueError). Returns "
           "{'changed', 'added': [its id], 'removed'}.")
        .def("add_material", [](PyScene& s, const py::object& diffuse, const py::object& ambient,
                                const py::object& specular, const py::object& reflective, const py::object& transparent,
                                const py::object& emissive, const py::object& shininess, const py::object& ior,
                                const py::object& texture, const py::object& blend, const py::object& repeat,
                                const py::object& bumpMap) {
            api::Material m;
            m.diffuse = vec3Arg("diffuse", diffuse);
            m.ambient = vec3Arg("ambient", ambient);
            m.specular = vec3Arg("specular", specular);
            m.reflective = vec3Arg("reflective", reflective);
            m.transparent = vec3Arg("transparent", transparent);
            m.emissive = vec3Arg("emissive", emissive);
            m.shininess = realOption("shininess", shininess);
            m.ior = realOption("ior", ior);
            m.blend = realOption("blend", blend);
            m.texture.texture = handleArg("texture", texture);
            m.bumpMap.texture = handleArg("bump_map", bumpMap);
            const auto repeats = numbersArg<2>("repeat", repeat);
            m.texture.repeatU = m.bumpMap.repeatU = repeats[0];
            m.texture.repeatV = m.bumpMap.repeatV = repeats[1];
            return s.scene.addMaterial(m);
        }, py::arg("diffuse") = Triple{1, 1, 1}, py::arg("ambient") = Triple{0, 0, 0},
           py::arg("specular") = Triple{0, 0, 0}, py::arg("reflective") = Triple{0, 0, 0},
           py::arg("transparent") = Triple{0, 0, 0}, py::arg("emissive") = Triple{0, 0, 0}, py::arg("shininess") = 0.0,
           py::arg("ior") = 1.0, py::arg("texture") = -1, py::arg("blend") = 0.0,
           py::arg("repeat") = std::array<double, 2>{1, 1}, py::arg("bump_map") = -1,
           "A material (SPEC section 1's fields); texture and bump_map are handles from add_texture, repeated "
           "repeat = (u, v) times. Returns its handle, for add_primitive. Values the scenefile loader refuses "
           "(a negative color or shininess, an ior of 0, a blend outside [0, 1]) raise InputError (a ValueError).")
        .def("add_texture", [](PyScene& s, const std::filesystem::path& file) {
            return s.scene.addTextureFromFile(file);
        }, py::arg("file"), "A texture from an image file (png, jpg, ...); returns its handle.")
        .def("add_texture", [](PyScene& s, const py::array& pixels) {
            checkImageArray(pixels, "a texture");
            checkArrayPixels(pixels, "a texture", api::kMaxTexturePixels, int64_t(api::kMaxTexturePixels),
                             "a texture file's budget of 2^25 pixels (8192 x 4096)");
            return s.scene.addTextureFromPixels(int(pixels.shape(1)), int(pixels.shape(0)), linearPixels(pixels));
        }, py::arg("pixels"),
           "A texture from an H x W x 3 array, row 0 at the top: floats (1.0 is full) or uint8 (255 is full). "
           "Returns its handle.")
        .def("add_mesh", [](PyScene& s, const py::object& positions, const py::object& triangles,
                            const py::object& normals, const py::object& uvs) {
            return s.scene.addMesh(flat<float>(positions, 3, "positions"), vertexIndices(triangles),
                                   flat<float>(normals, 3, "normals"), flat<float>(uvs, 2, "uvs"));
        }, py::arg("positions"), py::arg("triangles"), py::arg("normals") = py::none(), py::arg("uvs") = py::none(),
           "A triangle mesh from N x 3 positions and M x 3 vertex indices (counter-clockwise from the front), "
           "optionally N x 3 normals and N x 2 uvs. Returns its handle.")
        .def("add_primitive", [](const py::object& self, const std::string& type, const api::Transform& transform,
                                 int material, int mesh, const py::object& node) {
            PyScene& s = self.cast<PyScene&>();
            const int id = node.is_none() ? s.scene.addPrimitive(shape(type), transform, material, mesh)
                                          : s.scene.addPrimitiveTo(node.cast<int>(), shape(type), transform, material, mesh);
            return PyObjectHandle{self, &s.scene, id};
        }, py::arg("shape"), py::arg("transform") = api::Transform(), py::arg("material") = 0, py::arg("mesh") = -1,
           py::arg("node") = py::none(),
           "Places a unit shape ('cube', 'sphere', 'cylinder', 'cone', 'torus', or 'mesh' with a handle from "
           "add_mesh) with a material handle from add_material; returns its SceneObject. With node= (an id from "
           "nodes), it goes inside that transblock (in a master: in every instance), `transform` taking it to the "
           "transblock's frame; otherwise in a transblock of its own at the end of the root tree, `transform` "
           "object to world.")
        .def_property_readonly("primitive_count", [](const PyScene& s) { return s.scene.primitiveCount(); },
                               "How many primitives the scene holds.")
        .def_property_readonly("light_count", [](const PyScene& s) { return s.scene.lightCount(); },
                               "How many lights the scene holds.")
        .def_property_readonly("objects", [](const py::object& self) {
            return objectHandles(self, self.cast<PyScene&>().scene);
        }, "Every object (SceneObject handles), in the scenefile's order; objects added in code last.")
        .def("object", [](const py::object& self, int id) {
            PyScene& s = self.cast<PyScene&>();
            s.scene.object(id);  // raises InputError when there is none
            return PyObjectHandle{self, &s.scene, id};
        }, py::arg("id"), "The object with this id (a SceneObject); InputError when there is none.")
        .def("object_of_instance", [](const py::object& self, size_t instance) {
            PyScene& s = self.cast<PyScene&>();
            return PyObjectHandle{self, &s.scene, s.scene.objectOfInstance(instance)};
        }, py::arg("instance"), "The object that rendered primitive `instance` is an instance of.")
        .def_property_readonly("nodes", [](const PyScene& s) {
            py::list nodes;
            for (const api::SceneNode& node : s.scene.nodes()) {
                py::dict d;
                d["id"] = node.id;
                d["path"] = node.path;
                d["transform"] = node.toParent;
                d["masters"] = node.masters;
                nodes.append(d);
            }
            return nodes;
        }, "Every transblock, as dicts of id, path ('root/transblock[1]') and transform (to its parent's frame).")
        .def("set_node_transform", [](PyScene& s, int id, const api::Transform& t) { s.scene.setNodeTransform(id, t); },
             py::arg("id"), py::arg("transform"),
             "Replaces the transforms of transblock `id` (from nodes) with `transform`; it moves all it holds.")
        .def_property_readonly("lights", [](const PyScene& s) {
            py::list lights;
            for (const api::Light& light : s.scene.lights()) lights.append(lightDict(light));
            return lights;
        }, "The lights, as dicts of add_light's arguments, in order.")
        .def("set_light", [](PyScene& s, size_t index, const py::kwargs& fields) {
            std::vector<std::string> lights;
            for (const api::OutlineEntry& entry : s.scene.outline())
                if (entry.kind == "light") lights.push_back(entry.node);
            if (index >= lights.size())
                throw py::value_error("light " + std::to_string(index) + " does not exist (the scene has " +
                                      std::to_string(lights.size()) + ")");
            return resultDict(s.scene.set(lights[index], fieldValues("light", fields)));
        }, py::arg("index"),
           "Changes the fields given of light `index` (the field table's keywords, cs123ray.fields(): type, color, "
           "position, direction, function (the attenuation c1, c2, c3), angle, penumbra, width, height), keeping "
           "the others.")
        .def("remove_light", [](PyScene& s, size_t index) { s.scene.removeLight(index); }, py::arg("index"),
             "Removes light `index`; the later ones move down.")
        .def("outline", [](const PyScene& s) {
            py::list nodes;
            for (const api::OutlineEntry& entry : s.scene.outline())
                nodes.append(py::dict("node"_a = entry.node, "parent"_a = entry.parent.empty() ? py::object(py::none()) : py::object(py::str(entry.parent)),
                                      "depth"_a = entry.depth, "kind"_a = entry.kind, "label"_a = entry.label,
                                      "text"_a = entry.text, "path"_a = entry.path));
            return nodes;
        }, "Every node of the scene's tree, in document order, as dicts of node (its id: 'object-3', 'light-0', "
           "'block-2', 'tree-0', 'placement-1', 'camera', 'globals'), parent, depth, kind, label (the kind in the "
           "words of the scene's format: a JSON scene's 'group', 'template group', 'template use'), text and path "
           "(its place in the file: 'root/transblock[0]/object[1]', 'groups[1].primitives[0]').")
        .def("get", [](const PyScene& s, const py::handle& node, const std::string& field) {
            return fieldPython(s.scene.field(nodeArg("node", node), field));
        }, py::arg("node"), py::arg("field"), "Field `field` (its keyword or scenefile name) of `node`.")
        .def("set", [](PyScene& s, const py::handle& node, const py::kwargs& fields) {
            const std::string id = nodeArg("node", node);
            return resultDict(s.scene.set(id, fieldValues(ownerOf(id), fields)));
        }, py::arg("node"),
           "Sets fields of one node, all or none (keywords from cs123ray.fields()): an object's material, texture, "
           "transform (its own transblock's steps, [('translate', (x, y, z)), ...]) or world (a Transform: it moves "
           "alone); a light's; the camera's ('camera'); the globals' ('globals'); a transblock's transform; a "
           "tree's name. Returns {'changed', 'added', 'removed'}.")
        .def("add", [](PyScene& s, const std::string& shape, const py::object& parent, const py::object& file,
                       const py::kwargs& fields) {
            return resultDict(s.scene.add(shape, fieldValues("object", fields),
                                          parent.is_none() ? "" : nodeArg("parent", parent),
                                          file.is_none() ? std::filesystem::path() : std::filesystem::path(textOption("file", file))));
        }, py::arg("shape"), py::arg("parent") = py::none(), py::arg("file") = py::none(),
           "Adds a primitive ('cube', 'cylinder', 'cone', 'sphere', 'torus', or 'mesh' with file=, an .obj) in a "
           "transblock of its own, at the end of the root tree or in transblock `parent`, with its fields set. "
           "Returns {'changed', 'added': [the object, its transblock], 'removed'}.")
        .def("delete", [](PyScene& s, const py::args& nodes) { return resultDict(s.scene.remove(nodeArgs(nodes))); },
             "Removes the nodes given (objects, lights, transblocks with what they hold, placements, csg objects).")
        .def("duplicate", [](PyScene& s, const py::args& nodes) { return resultDict(s.scene.duplicate(nodeArgs(nodes))); },
             "A copy of each node given, right after it.")
        .def("group", [](PyScene& s, const py::args& nodes) { return resultDict(s.scene.group(nodeArgs(nodes))); },
             "Moves the objects given (of one transblock) into a new transblock there.")
        .def("rename", [](PyScene& s, const py::handle& tree, const py::handle& name) {
            return resultDict(s.scene.rename(nodeArg("tree", tree), textOption("name", name)));
        }, py::arg("tree"), py::arg("name"), "Renames a tree (a master) and every placement of it.")
        .def("make_unique", [](PyScene& s, const py::handle& placement) {
            return resultDict(s.scene.makeUnique(nodeArg("placement", placement)));
        }, py::arg("placement"), "Gives a placement of a master a copy of the master of its own.")
        .def("save", [](const PyScene& s, const std::filesystem::path& file, bool replaceReadOnly, bool overwriteChanges) {
            s.scene.save(file, api::WriteOptions{replaceReadOnly, overwriteChanges});
        }, py::arg("file"), py::kw_only(), py::arg("replace_read_only") = false, py::arg("overwrite_changes") = false,
             "Writes the scene as a CS123 scenefile (whole or not at all) that loads back to the same render, "
             "masters kept as masters, texture and mesh paths relative to `file`; a file named .json gets the "
             "course's JSON (masters as templates; what JSON cannot hold, a torus say, raises InputError). A link is written through to "
             "its file, which keeps its mode; a read-only file raises InputError unless replace_read_only=True. "
             "A file this scene was loaded from or saved to that another program has changed since is not "
             "replaced (InputError) unless overwrite_changes=True.")
        .def("to_text", [](const PyScene& s) { return s.scene.toText(); },
             "The scene as CS123 scenefile text (what save writes).")
        .def("_assign", [](PyScene& s, const PyScene& other) {
            s.scene = other.scene;
            s.warnings = other.warnings;
        }, py::arg("other"),
           "Makes this scene a copy of `other`, in place (a studio's edits read into the notebook's scene).")
        .def("__repr__", &sceneRepr);
}

void bindLoading(py::module_& m) {
    m.def("load_scene", [](const std::filesystem::path& file, std::vector<std::filesystem::path> searchPaths,
                           bool strict, bool textures) {
        api::LoadResult loaded = api::Scene::load(file, loadOptions(searchPaths, strict, textures));
        return PyScene{std::move(loaded.scene), std::move(loaded.warnings)};
    }, py::arg("file"), py::arg("search_paths") = std::vector<std::filesystem::path>{}, py::arg("strict") = false,
       py::arg("textures") = true,
       "Reads a scenefile, XML or the course's JSON (texture and mesh files also looked for under search_paths). Its warnings are in "
       ".warnings; strict=True makes them errors; textures=False skips reading images. Raises InputError.");
    m.def("scene_from_string", [](const std::string& xml, const std::filesystem::path& name,
                                  std::vector<std::filesystem::path> searchPaths, bool strict) {
        api::LoadResult loaded = api::Scene::fromString(xml, name, loadOptions(searchPaths, strict, true));
        return PyScene{std::move(loaded.scene), std::move(loaded.warnings)};
    }, py::arg("xml"), py::arg("name") = "scene.xml", py::arg("search_paths") = std::vector<std::filesystem::path>{},
       py::arg("strict") = false,
       "Reads scenefile XML or JSON (text starting with '{') from a string; `name` stands for the file in messages, and relative texture and mesh "
       "paths are found from its folder. Raises InputError.");
}

void bindRendering(py::module_& m) {
    m.def("fields", [] {
        py::list fields;
        for (const api::FieldInfo& f : fieldTable())
            fields.append(py::dict("owner"_a = f.owner, "group"_a = f.group, "name"_a = f.name, "keyword"_a = f.keyword,
                                   "kind"_a = f.kind, "help"_a = f.help, "min"_a = f.min, "max"_a = f.max,
                                   "min_included"_a = f.minIncluded, "max_included"_a = f.maxIncluded,
                                   "lights"_a = f.lights, "choices"_a = f.choices));
        return fields;
    }, "The editable fields, from the one table every editor reads (ray view's page, C++, Python): dicts of owner "
       "(object, light, camera, globals, transblock, tree), group, name (the scenefile's), keyword (for Scene.set), "
       "kind, help, range, the light types using it, choices.");
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
    }, "The OpenCL devices, as dicts (index, name, platform, gpu, cpu), numbered as device=<index> takes them.");

    py::class_<PyPick>(m, "Pick", "What a pixel shows (Renderer.pick): the surface its camera ray meets first.")
        .def_property_readonly("object", [](const PyPick& p) { return p.object; },
                               "The scene's object hit (a SceneObject of renderer.scene: its path, material, "
                               "transform, edits).")
        .def_property_readonly("object_id", [](const PyPick& p) { return p.hit.object; },
                               "Its stable id (renderer.scene.object(id)).")
        .def_readonly("path", &PyPick::path, "Its place in the scenefile's tree ('root/transblock[1]/object[0]').")
        .def_property_readonly("instance", [](const PyPick& p) { return p.hit.instance; },
                               "The primitive instance hit: its index among the scene's primitives (flattened).")
        .def_property_readonly("point", [](const PyPick& p) { return pyTuple(p.hit.point); },
                               "The hit point (world space), a tuple.")
        .def_property_readonly("normal", [](const PyPick& p) { return pyTuple(p.hit.normal); },
                               "The surface's outward unit normal there (world space), a tuple.")
        .def_property_readonly("distance", [](const PyPick& p) { return p.hit.distance; }, "From the eye to the point.")
        .def("__repr__", [](const PyPick& p) { return pickRepr(p.hit, p.path); });

    py::class_<PyRenderer>(m, "Renderer", "Renders one scene on one device selection, frame after frame.")
        .def(py::init([](const PyScene& s, const std::string& device) {
            auto r = std::make_unique<PyRenderer>();
            r->scene = std::make_shared<PyScene>(s);
            // The renderer shares the scene object Python sees as renderer.scene.
            r->renderer = std::make_unique<api::Renderer>(std::shared_ptr<api::Scene>(r->scene, &r->scene->scene), device);
            return r;
        }), py::arg("scene"), py::arg("device") = "auto",
           "device: 'auto' (a GPU, else an OpenCL CPU), 'cpu', 'gpu', 'all', an index from list_devices(), a list "
           "of indices ('0,2'), or 'ref' (the double-precision host renderer, no OpenCL). The scene is copied: "
           "renderer.scene is the renderer's own, and edits to it are what the next frame renders.")
        .def_property_readonly("device", [](const PyRenderer& r) { return r.renderer->devices(); },
                               "The device selection it was made with.")
        .def_property_readonly("scene", [](const PyRenderer& r) { return r.scene; },
                               "The scene it renders (its own copy): edit it between frames, and each frame takes "
                               "the edits made since the last (on OpenCL devices only what changed is packed and "
                               "uploaded again; see stats).")
        .def_property_readonly("stats", [](const PyRenderer& r) { return statsDict(r.stats); },
                               "The last frame's statistics, a dict (empty before the first frame): device, "
                               "primary_rays, shadow_rays, secondary_rays, pack_seconds, bvh_build_seconds, "
                               "upload_seconds (0 where the frame kept what an earlier one packed or uploaded), "
                               "kernel_build_seconds, render_seconds, cancelled.")
        .def("pick", [](PyRenderer& r, int x, int y) -> py::object {
            std::optional<api::Pick> hit = r.renderer->pick(x, y);
            if (!hit) return py::none();
            PyPick pick{*hit, py::none(), ""};
            if (hit->object >= 0) {
                // The handle holds the renderer's Scene object, as renderer.scene.objects' do.
                pick.object = py::cast(PyObjectHandle{py::cast(r.scene), &r.scene->scene, hit->object});
                pick.path = r.scene->scene.object(hit->object).path;
            }
            return py::cast(pick);
        }, py::arg("x"), py::arg("y"),
           "What the camera ray through the centre of pixel (x, y) (of the current width and height; row 0 at the "
           "top) meets first, as a Pick, or None on the background. Found on the host, so every device gives "
           "the same answer. A pixel outside the image raises InputError (a ValueError).")
        .def("set_camera", [](PyRenderer& pr, const py::handle& position, const py::handle& look, const py::handle& up,
                              const py::handle& heightAngle) {
            api::Renderer& r = *pr.renderer;
            api::Camera c = r.camera();
            c.position = vec3Arg("position", position);
            c.look = vec3Arg("look", look);
            c.up = vec3Arg("up", up);
            c.heightAngleDegrees = realOption("height_angle", heightAngle);
            r.setCamera(c);
        }, py::arg("position"), py::arg("look"), py::arg("up") = Triple{0, 1, 0}, py::arg("height_angle") = 45.0,
           "Moves the camera for the next frames (the lens stays as the scene set it).")
        .def("set_options", [](PyRenderer& pr, const py::kwargs& options) {
            pr.renderer->setSettings(settingsFrom(options, pr.renderer->settings()));
        }, ("Changes render options for the next frames, as keywords: " + optionNames() +
            " (width and height together). A wrong type raises TypeError, a value out of range InputError (a "
            "ValueError).").c_str())
        .def("render", [](PyRenderer& r, const py::object& dtype, const py::object& progress) {
            api::FrameStats stats;
            py::array image = renderArray(*r.renderer, dtype, progress, &stats);
            r.stats = stats;
            return image;
        }, py::arg("dtype") = "float32", py::arg("progress") = py::none(),
           "Renders a frame: an H x W x 3 array (a RenderedImage, which a notebook shows as a picture), float32 "
           "(linear, unclamped) or uint8 (the bytes of ray's 8-bit images). progress(fraction) is called now and "
           "then; Ctrl-C raises KeyboardInterrupt within a second.")
        .def("__repr__", [](const PyRenderer& r) { return rendererRepr(*r.renderer); });

    m.def("render", [](const PyScene& s, const std::string& device, const py::object& dtype,
                       const py::object& progress, const py::kwargs& options) {
        api::Renderer renderer(s.scene, device);
        renderer.setSettings(settingsFrom(options, renderer.settings()));
        return renderArray(renderer, dtype, progress);
    }, py::arg("scene"), py::arg("device") = "auto", py::arg("dtype") = "float32", py::arg("progress") = py::none(),
       "Renders the scene once: an H x W x 3 array (a RenderedImage, which a notebook shows as a picture; "
       "float32 linear, or uint8 as ray's PNGs). device and the options (keywords) as Renderer and "
       "Renderer.set_options take them.");

    m.def("save_image", &saveArray, py::arg("image"), py::arg("file"), py::kw_only(), py::arg("replace_read_only") = false,
          "Writes an H x W x 3 array, floats (linear, 1.0 is full) or uint8 (as render(dtype='uint8') makes), in "
          "the format the extension names (png, jpg, ppm, tif: 8-bit; exr, hdr: floats), at most 16384 pixels a "
          "side. The file is replaced whole or not at all; a read-only file raises InputError unless "
          "replace_read_only=True.");
}

// ---------------------------------------------------------------------------------------
// pybind11's own argument errors in plain words. When no overload takes the arguments,
// pybind11 raises a TypeError listing C++ signatures ("incompatible function arguments. The
// following argument types are supported: 1. (self: cs123ray.Scene, ...) Invoked with:
// ..."), and a few of its failures say "Internal error: ...". Each function of the module
// is wrapped so that these become a sentence: an unknown keyword with the closest one
// ("did you mean 'diffuse'?"), or what the function takes.

// The parameter names in a pybind11 docstring's signature lines ("add_material(self:
// cs123ray.Scene, diffuse: object = None, ...) -> int"), self left out.
py::list parameterNames(const py::handle& function) {
    const py::object doc = py::getattr(function, "__doc__", py::none());
    py::list names;
    if (doc.is_none()) return names;
    py::list found = py::module_::import("re").attr("findall")(R"([(,]\s*(\w+)\s*:)", doc);
    for (const py::handle& name : found)
        if (std::string(py::str(name)) != "self" && !names.contains(name)) names.append(name);
    return names;
}

std::string joined(const py::list& names) {
    std::string text;
    for (const py::handle& name : names) text += (text.empty() ? "" : ", ") + std::string(py::str(name));
    return text;
}

// The sentence for pybind11's message about a call of `name` with `kwargs`; empty when the
// message is none of pybind11's own.
std::string plainArgumentError(const std::string& message, const std::string& name, const py::handle& function,
                               const py::kwargs& kwargs) {
    const bool mismatch = message.find("incompatible function arguments") != std::string::npos ||
                          message.find("incompatible constructor arguments") != std::string::npos;
    if (!mismatch && message.rfind("Internal error", 0) != 0 && message.find("Unable to cast") == std::string::npos)
        return "";
    const py::list names = parameterNames(function);
    for (const auto& [key, value] : kwargs) {
        if (names.contains(key)) continue;
        py::list close = py::module_::import("difflib").attr("get_close_matches")(key, names, 1);
        return name + "() has no argument '" + std::string(py::str(key)) + "'" +
               (close.empty() ? "" : "; did you mean '" + std::string(py::str(close[0])) + "'?") +
               (names.empty() ? "" : " (it takes " + joined(names) + ")");
    }
    return name + "() cannot take these arguments (a missing one, or one of the wrong type)" +
           (names.empty() ? "" : "; it takes " + joined(names)) + ": see help(cs123ray)";
}

py::cpp_function withPlainArgumentErrors(const py::object& function, const std::string& name,
                                         const py::object& scope, bool method) {
    // The wrapper's docstring is the function's own, whose first lines are its signatures
    // (help() and the stubs' test read them): not pybind11's "(*args, **kwargs)".
    py::options options;
    options.disable_function_signatures();
    auto call = [function, name](const py::args& args, const py::kwargs& kwargs) -> py::object {
        try {
            return function(*args, **kwargs);
        } catch (py::error_already_set& e) {
            if (!e.matches(PyExc_TypeError) && !e.matches(PyExc_RuntimeError)) throw;
            const std::string plain = plainArgumentError(py::str(e.value()), name, function, kwargs);
            if (plain.empty()) throw;
            throw py::type_error(plain);
        }
    };
    const std::string doc = py::str(py::getattr(function, "__doc__", py::str("")));
    if (method) return py::cpp_function(call, py::name(name.c_str()), py::is_method(scope), py::doc(doc.c_str()));
    return py::cpp_function(call, py::name(name.c_str()), py::scope(scope), py::doc(doc.c_str()));
}

// Every function of the module and method of its classes (not their dunders: pybind11 keeps
// __init__ for itself), wrapped.
void plainArgumentErrors(py::module_& m) {
    const py::dict names = py::module_::import("builtins").attr("dict")(m.attr("__dict__"));  // a copy: m changes
    for (const auto& [key, value] : names) {
        const std::string name = py::str(key);
        if (name.rfind("__", 0) == 0) continue;
        if (PyCFunction_Check(value.ptr())) {
            m.attr(key) = withPlainArgumentErrors(py::reinterpret_borrow<py::object>(value), name, m, false);
        } else if (PyType_Check(value.ptr()) && !PyType_IsSubtype(reinterpret_cast<PyTypeObject*>(value.ptr()),
                                                                  reinterpret_cast<PyTypeObject*>(PyExc_BaseException))) {
            const py::object cls = py::reinterpret_borrow<py::object>(value);
            const py::dict members = py::module_::import("builtins").attr("dict")(cls.attr("__dict__"));
            for (const auto& [memberKey, member] : members) {
                const std::string memberName = py::str(memberKey);
                if (memberName.rfind("__", 0) == 0 || !PyInstanceMethod_Check(member.ptr())) continue;
                const py::object function = py::reinterpret_borrow<py::object>(PyInstanceMethod_GET_FUNCTION(member.ptr()));
                py::setattr(cls, memberKey, withPlainArgumentErrors(function, memberName, cls, true));
            }
        }
    }
}

}  // namespace

PYBIND11_MODULE(cs123ray, m) {
    requireNumpy();
    m.doc() = "ray, the CS123 scenefile ray tracer: load or build a scene, render it to a NumPy array. In Jupyter "
              "a render shows itself as a picture, a scene as a small picture and its outline, and view(scene) "
              "opens the studio (ray view) on the scene inside the notebook.";
    m.attr("__version__") = api::version();
    registerErrors(m);
    bindTransform(m);
    py::class_<PyScene, std::shared_ptr<PyScene>> scene(m, "Scene", "A scene: Scene() builds one in code; load_scene() reads a scenefile.");
    bindScene(scene);
    bindSceneObject(m);
    bindLoading(m);
    bindRendering(m);
    // Plain argument errors wrap the C++ functions first; the notebook's Python (its studios'
    // synchronization) then wraps those.
    plainArgumentErrors(m);
    py::exec(kNotebookPython, m.attr("__dict__"));
    renderedImageType() = m.attr("RenderedImage");
}
