// The `ray` command as a user meets it: arguments, exit statuses, messages, outputs.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "app/cli.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using ray::test::runRay;
using Catch::Matchers::Contains;

std::string scene(const std::string& name) { return (ray::test::scenesDir() / name).string(); }

fs::path freshOutput(const std::string& name) {
    fs::path file = ray::test::outputDir() / "cli" / name;
    fs::create_directories(file.parent_path());
    fs::remove(file);
    return file;
}

std::string readText(const fs::path& file) {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST_CASE("positional arguments follow the course demo", "[cli]") {
    using ray::parseCommandLine;
    auto o = parseCommandLine({"a.xml"});
    CHECK(o.settings.width == 1024);
    CHECK(o.settings.height == 768);
    CHECK(o.settings.maxDepth == 4);
    o = parseCommandLine({"a.xml", "320", "240"});
    CHECK(o.settings.width == 320);
    CHECK(o.settings.height == 240);
    o = parseCommandLine({"a.xml", "320", "240", "7"});
    CHECK(o.settings.maxDepth == 7);
    o = parseCommandLine({"a.xml", "2"});
    CHECK(o.settings.maxDepth == 2);
    CHECK(ray::outputPathFor(parseCommandLine({"dir/My Scene.xml"})) == fs::path("My Scene.png"));
    CHECK(o.settings.antialias == ray::AntialiasMode::Course);
}

TEST_CASE("bad arguments are refused with a reason", "[cli]") {
    using ray::parseCommandLine;
    using ray::UsageError;
    CHECK_THROWS_AS(parseCommandLine({}), UsageError);
    CHECK_THROWS_WITH(parseCommandLine({"a.xml", "0", "10"}), Contains("width must be between 1"));
    CHECK_THROWS_WITH(parseCommandLine({"a.xml", "10", "abc"}), Contains("height must be a whole number"));
    CHECK_THROWS_WITH(parseCommandLine({"a.xml", "10", "10", "-1"}), Contains("depth"));
    CHECK_THROWS_WITH(parseCommandLine({"a.xml", "--aa", "fast"}), Contains("--aa must be"));
    CHECK_THROWS_WITH(parseCommandLine({"a.xml", "--bogus"}), Contains("unknown option '--bogus'"));
    CHECK_THROWS_WITH(parseCommandLine({"a.xml", "--output"}), Contains("--output needs a value"));
    CHECK_THROWS_WITH(parseCommandLine({"a.xml", "--device", "tpu"}), Contains("--device"));
    CHECK_THROWS_WITH(parseCommandLine({"a.xml", "--samples", "8"}), Contains("--aa stratified"));
    CHECK_THROWS_WITH(parseCommandLine({"a.xml", "1", "2", "3", "4"}), Contains("too many arguments"));
    CHECK_THROWS_WITH(parseCommandLine({"a.xml", "--no-bvh"}), Contains("add --device ref"));
    CHECK_THROWS_WITH(parseCommandLine({"a.xml", "--no-bvh", "--device", "cpu"}), Contains("add --device ref"));
    CHECK(parseCommandLine({"a.xml", "--no-bvh", "--device", "ref"}).referenceBruteForce);
}

TEST_CASE("the reference renderer with --no-bvh renders what it renders with its BVH", "[cli]") {
    fs::path withBvh = freshOutput("bvh_on.exr"), withoutBvh = freshOutput("bvh_off.exr");
    fs::path json = freshOutput("bvh_off.json");
    auto a = runRay({scene("showpiece.xml"), "48", "36", "--device", "ref", "--quiet", "-o", withBvh.string()});
    auto b = runRay({scene("showpiece.xml"), "48", "36", "--device", "ref", "--no-bvh", "--quiet", "-o",
                     withoutBvh.string(), "--stats-json", json.string()});
    REQUIRE(a.exitCode == 0);
    REQUIRE(b.exitCode == 0);
    CHECK(ray::readImage(withBvh).rgb == ray::readImage(withoutBvh).rgb);
    CHECK_THAT(readText(json), Contains("no BVH"));
}

TEST_CASE("help and version exit 0", "[cli]") {
    auto help = runRay({"--help"});
    CHECK(help.exitCode == 0);
    CHECK_THAT(help.output, Contains("usage: ray <scene.xml>"));
    auto version = runRay({"--version"});
    CHECK(version.exitCode == 0);
    CHECK_THAT(version.output, Contains("ray "));
}

TEST_CASE("a bad argument exits 2 and points at --help", "[cli]") {
    auto r = runRay({scene("shadows.xml"), "--aa", "sideways"});
    CHECK(r.exitCode == 2);
    CHECK_THAT(r.output, Contains("see ray --help"));
}

TEST_CASE("a scene that does not exist or does not parse exits 2, writing nothing", "[cli]") {
    fs::path out = freshOutput("missing.png");
    auto r = runRay({"/nonexistent/scene.xml", "-o", out.string(), "--device", "ref"});
    CHECK(r.exitCode == 2);
    CHECK_THAT(r.output, Contains("/nonexistent/scene.xml"));
    CHECK_FALSE(fs::exists(out));

    fs::path broken = ray::test::outputDir() / "cli" / "broken.xml";
    std::ofstream(broken) << "<scenefile>\n<object type=\"tree\" name=\"root\">\n<transblock>\n</scenefile>\n";
    r = runRay({broken.string(), "-o", out.string(), "--device", "ref"});
    CHECK(r.exitCode == 2);
    CHECK_THAT(r.output, Contains("broken.xml:"));
    CHECK_FALSE(fs::exists(out));
}

TEST_CASE("an unknown output format is refused before rendering", "[cli]") {
    auto r = runRay({scene("shadows.xml"), "-o", (ray::test::outputDir() / "out.xyz").string()});
    CHECK(r.exitCode == 2);
    CHECK_THAT(r.output, Contains("extension"));
    r = runRay({scene("shadows.xml"), "-o", (ray::test::outputDir() / "no_extension").string()});
    CHECK(r.exitCode == 2);
    // A format OpenImageIO reads but cannot write (pfm, in Debian 12's build) is refused
    // up front too, not after the render.
    if (!ray::canWriteImageFormat("out.pfm")) {
        r = runRay({scene("shadows.xml"), "-o", (ray::test::outputDir() / "out.pfm").string(), "--device", "ref"});
        CHECK(r.exitCode == 2);
        CHECK_THAT(r.output, Contains(".exr"));
    }
    r = runRay({scene("shadows.xml"), "-o", "/nonexistent-folder/out.png"});
    CHECK(r.exitCode == 2);
    CHECK_THAT(r.output, Contains("does not exist"));
}

TEST_CASE("an existing output survives a failed render untouched", "[cli]") {
    fs::path out = freshOutput("keep.png");
    std::ofstream(out) << "precious";
    auto r = runRay({"/nonexistent/scene.xml", "-o", out.string(), "--device", "ref"});
    CHECK(r.exitCode == 2);
    CHECK(readText(out) == "precious");
}

TEST_CASE("renders write the image and statistics", "[cli]") {
    for (std::string device : {"ref", "cpu"}) {
        DYNAMIC_SECTION(device) {
            fs::path out = freshOutput("stats_" + device + ".png");
            fs::path json = freshOutput("stats_" + device + ".json");
            auto r = runRay({scene("shadows.xml"), "64", "48", "2", "--device", device, "--quiet", "-o", out.string(),
                             "--stats", "--stats-json", json.string()});
            if (device == "cpu" && r.exitCode == 3) {
                ray::test::skip("no OpenCL CPU device");
                return;
            }
            REQUIRE(r.exitCode == 0);
            ray::Image image = ray::readImage(out);
            CHECK(image.width == 64);
            CHECK(image.height == 48);
            CHECK_THAT(r.output, Contains("Mrays/s"));
            std::string stats = readText(json);
            for (const char* key : {"\"width\": 64", "\"height\": 48", "\"depth\": 2", "\"device\"", "\"primary_rays\"",
                                    "\"shadow_rays\"", "\"secondary_rays\"", "\"total_rays\"", "\"load_seconds\"",
                                    "\"bvh_build_seconds\"", "\"kernel_build_seconds\"", "\"render_seconds\"",
                                    "\"mrays_per_second\""})
                CHECK_THAT(stats, Contains(key));
        }
    }
}

// --stats's memory line: the process's peak and, for a scene with meshes, their triangles
// and bytes a triangle (as loaded; as packed on an OpenCL device). mesh_vase.xml: one mesh
// (vase.obj) used by three instances, counted once.
TEST_CASE("ray --stats reports peak memory and a mesh's bytes a triangle", "[cli][mesh]") {
    const ray::Scene loaded = ray::loadScene(scene("mesh_vase.xml"));
    REQUIRE(loaded.meshes.size() == 1);
    const std::string triangles = std::to_string(loaded.meshes[0].triangles.size()) + " triangles";
    for (std::string device : {"ref", "cpu"}) {
        DYNAMIC_SECTION(device) {
            fs::path json = freshOutput("memory_" + device + ".json");
            auto r = runRay({scene("mesh_vase.xml"), "32", "24", "1", "--device", device, "--quiet", "-o",
                             freshOutput("memory_" + device + ".png").string(), "--stats", "--stats-json",
                             json.string()});
            if (device == "cpu" && r.exitCode == 3) {
                ray::test::skip("no OpenCL CPU device");
                return;
            }
            REQUIRE(r.exitCode == 0);
            CHECK_THAT(r.output, Contains("memory       peak ") && Contains("; meshes " + triangles + ", ") &&
                                     Contains(" bytes a triangle loaded, ") && Contains(" at peak"));
            // Only an OpenCL device packs the mesh.
            CHECK((r.output.find(" packed, ") != std::string::npos) == (device == "cpu"));
            const std::string stats = readText(json);
            for (const char* key : {"\"peak_memory_bytes\"", "\"mesh_triangles\"", "\"mesh_loaded_bytes\"",
                                    "\"mesh_packed_bytes\""})
                CHECK_THAT(stats, Contains(key));
            CHECK_THAT(stats, !Contains("\"peak_memory_bytes\": 0,"));
        }
    }
}

TEST_CASE("float outputs keep values above 1", "[cli]") {
    fs::path out = freshOutput("bright.exr");
    auto r = runRay({scene("light_point.xml"), "32", "24", "--aa", "off", "--device", "ref", "--quiet", "-o", out.string()});
    REQUIRE(r.exitCode == 0);
    ray::Image image = ray::readImage(out);
    REQUIRE(image.width == 32);
}

TEST_CASE("no OpenCL platform is a clear message naming PoCL and the reference renderer", "[cli]") {
    // The ICD loader reads its vendor list from this folder: an empty one means no platform.
    fs::path empty = ray::test::outputDir() / "no_icds";
    fs::create_directories(empty);
    auto r = runRay({scene("shadows.xml"), "32", "24", "--device", "cpu", "-o", (empty / "x.png").string()}, 60,
                    {"OCL_ICD_VENDORS=" + empty.string()});
    CHECK(r.exitCode == 3);
    CHECK_THAT(r.output, Contains("no OpenCL platform"));
    CHECK_THAT(r.output, Contains("pocl"));
    CHECK_THAT(r.output, Contains("--device ref"));
    auto list = runRay({"--list-devices"}, 60, {"OCL_ICD_VENDORS=" + empty.string()});
    CHECK(list.exitCode == 0);
    CHECK_THAT(list.output, Contains("no OpenCL platform"));
}

TEST_CASE("an OpenCL device index that does not exist is a device error", "[cli]") {
    auto r = runRay({scene("shadows.xml"), "32", "24", "--device", "99", "-o", (ray::test::outputDir() / "x.png").string()});
    CHECK(r.exitCode == 3);
    CHECK_THAT(r.output, Contains("--list-devices"));
}

// The kernel binaries in ray's cache folder (beside them PoCL's own folder, pocl/).
static long kernelBinaries(const fs::path& cache) {
    return std::count_if(fs::directory_iterator(cache), fs::directory_iterator(),
                         [](const fs::directory_entry& e) { return e.is_regular_file(); });
}

TEST_CASE("the second run of a scene reuses the cached kernel", "[cli][kernel]") {
    fs::path cache = ray::test::outputDir() / "kernel_cache";
    fs::remove_all(cache);
    std::vector<std::string> env{"RAY_CACHE_DIR=" + cache.string()};
    fs::path json = freshOutput("cache.json");
    std::vector<std::string> args{scene("shadows.xml"), "16", "12", "--device", "cpu", "--quiet",
                                  "-o", (ray::test::outputDir() / "cache.png").string(), "--stats-json", json.string()};
    auto cold = runRay(args, 120, env);
    if (cold.exitCode == 3) {
        ray::test::skip("no OpenCL CPU device");
        return;
    }
    REQUIRE(cold.exitCode == 0);
    REQUIRE(fs::exists(cache));
    // One kernel binary and no temporary file; beside them PoCL's own cache, pocl/, which
    // ray points POCL_CACHE_DIR at when it is unset (opencl_device.cpp).
    CHECK(kernelBinaries(cache) == 1);
    const auto built = fs::last_write_time(*std::find_if(
        fs::directory_iterator(cache), fs::directory_iterator(), [](const fs::directory_entry& e) { return e.is_regular_file(); }));
    auto warm = runRay(args, 120, env);
    REQUIRE(warm.exitCode == 0);
    // Warm: the binary is read from the cache, not built and written again.
    CHECK(kernelBinaries(cache) == 1);
    for (const auto& e : fs::directory_iterator(cache))
        if (e.is_regular_file()) CHECK(e.last_write_time() == built);
}

TEST_CASE("depths 1 to 10 one after another wait for two kernel builds", "[cli][kernel]") {
    // The depth is a launch parameter; the kernel's frame stack comes in buckets
    // (host/opencl/kernel_build.h kernelFrames): 1-4 share one build, 5-10 another.
    fs::path cache = ray::test::outputDir() / "kernel_cache_depths";
    fs::remove_all(cache);
    std::vector<std::string> env{"RAY_CACHE_DIR=" + cache.string()};
    for (int depth = 1; depth <= 10; ++depth) {
        auto r = runRay({scene("shadows.xml"), "8", "6", std::to_string(depth), "--device", "cpu", "--quiet", "-o",
                         (ray::test::outputDir() / "depths.png").string()},
                        120, env);
        if (r.exitCode == 3) {
            ray::test::skip("no OpenCL CPU device");
            return;
        }
        REQUIRE(r.exitCode == 0);
    }
    CHECK(kernelBinaries(cache) == 2);
}

TEST_CASE("the option --course-meshes parses and is off by default", "[cli][course-meshes]") {
    using ray::kUsageText;
    using ray::parseCommandLine;
    CHECK_FALSE(parseCommandLine({"a.xml"}).settings.courseMeshes);
    CHECK(parseCommandLine({"a.xml", "--course-meshes"}).settings.courseMeshes);
    CHECK(std::string(kUsageText).find("--course-meshes") != std::string::npos);
}

namespace {

// What CLI11 says on its own; none of it may reach a user of any subcommand.
const std::vector<std::string> kCli11Wording = {"FAILED", "Could not convert", "required", "TEXT", " INT",
                                                "(0x)", "not in range", "Check ", "ArgumentMismatch",
                                                "The following argument", "was not expected", "REQUIRED",
                                                "Value ", "OR {", "->", "not a device selection"};

// The options a subcommand's --help lists, with whether each takes a value ("--aa MODE").
std::vector<std::pair<std::string, bool>> optionsInHelp(const std::string& help) {
    std::vector<std::pair<std::string, bool>> options;
    const size_t begin = help.find("\noptions:"), end = help.find("\nexit status");
    REQUIRE(begin != std::string::npos);
    REQUIRE(end != std::string::npos);
    const std::string section = help.substr(begin, end - begin);
    for (size_t at = section.find("--"); at != std::string::npos; at = section.find("--", at + 2)) {
        if (at > 0 && section[at - 1] != ' ' && section[at - 1] != '\n') continue;
        size_t stop = section.find_first_not_of("abcdefghijklmnopqrstuvwxyz-", at + 2);
        const std::string name = section.substr(at, stop - at);
        const bool takesValue = stop + 1 < section.size() && section[stop] == ' ' && std::isupper(section[stop + 1]);
        // Only the option's own line, not a mention in another's description.
        const size_t lineStart = section.rfind('\n', at) + 1;
        const std::string before = section.substr(lineStart, at - lineStart);
        if (before.find_first_not_of(" ,-abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ") != std::string::npos) continue;
        if (before.size() > 0 && before.find_first_not_of(' ') != std::string::npos &&
            before.find(", ") == std::string::npos)
            continue;
        if (std::none_of(options.begin(), options.end(), [&](auto& o) { return o.first == name; }))
            options.emplace_back(name, takesValue);
    }
    return options;
}

}  // namespace

TEST_CASE("every parse error of every subcommand is a plain sentence naming the option", "[cli][sweep]") {
    // A scene that does not exist, in a folder that does not exist either (ray view opens a
    // missing .xml file in an existing folder as a new scene): a value that is (wrongly or
    // rightly) accepted then stops at the load, so nothing renders or listens.
    const std::string missing = (ray::test::outputDir() / "sweep_no_such_folder" / "sweep_no_such_scene.xml").string();
    const std::vector<std::pair<std::vector<std::string>, std::string>> commands = {
        {{missing}, "ray"}, {{"view", missing, "--port", "0"}, "ray view"}, {{"explain", missing, "1", "1"}, "ray explain"}};
    const std::vector<std::string> badValues = {"", "bogus", "-1", "1e999", "99999999999", "0.5x", "nan"};
    int runs = 0;
    for (const auto& [base, name] : commands) {
        std::vector<std::string> helpArgs(base.begin(), base.begin() + (name == "ray" ? 0 : 1));
        helpArgs.push_back("--help");
        auto help = runRay(helpArgs);
        REQUIRE(help.exitCode == 0);
        const auto options = optionsInHelp(help.output);
        INFO(name << " --help lists " << options.size() << " options");
        REQUIRE(options.size() >= 8);

        auto check = [&](std::vector<std::string> args, const std::string& option, const std::string& value) {
            auto r = runRay(args, 60);
            ++runs;
            std::string shown;
            for (const std::string& a : args) shown += " " + a;
            INFO(name << ":" << shown << "\n-> exit " << r.exitCode << ": " << r.output);
            // 2, or 3 where a device index that parses names no device (ray view selects
            // its devices before it loads the scene).
            const bool noSuchDevice = r.exitCode == 3 && r.output.find("no OpenCL device " + value) != std::string::npos;
            CHECK((r.exitCode == 2 || noSuchDevice));
            for (const std::string& words : kCli11Wording) CHECK_THAT(r.output, !Contains(words));
            // A parse error names the option; a value taken stops at the missing scene.
            const bool namesOption = r.output.find(option) != std::string::npos ||
                                     (!value.empty() && r.output.find("'" + value + "'") != std::string::npos);
            CHECK((namesOption || noSuchDevice || r.output.find("sweep_no_such_scene.xml") != std::string::npos));
            if (r.output.find("(see " + name + " --help)") != std::string::npos) CHECK(namesOption);
        };
        for (const auto& [option, takesValue] : options) {
            if (!takesValue) {
                auto args = base;
                args.push_back(option + "=bogus");
                check(args, option, "");
                continue;
            }
            auto args = base;
            args.push_back(option);  // no value
            check(args, option, "");
            for (const std::string& value : badValues) {
                auto withValue = base;
                withValue.push_back(option);
                withValue.push_back(value);
                check(withValue, option, value);
            }
        }
        // Unknown options, with and without a guess.
        auto args = base;
        args.push_back("--zzzzzz");
        check(args, "--zzzzzz", "");
        args = base;
        args.push_back("--shadow");
        if (name != "ray view") {
            auto r = runRay(args);
            CHECK(r.exitCode == 2);
            CHECK_THAT(r.output, Contains("unknown option '--shadow'; did you mean --no-shadows?"));
        }
    }
    INFO(runs << " runs");
    CHECK(runs > 150);
}

TEST_CASE("the CLI points at what was meant", "[cli]") {
    const std::string chess = scene("shadows.xml");
    auto r = runRay({"--help"});
    CHECK_THAT(r.output, Contains("ray view <scene.xml>"));
    CHECK_THAT(r.output, Contains("ray explain <scene.xml> <x> <y>"));
    r = runRay({"vie", chess});
    CHECK(r.exitCode == 2);
    CHECK_THAT(r.output, Contains("unknown subcommand 'vie'"));
    CHECK_THAT(r.output, Contains("did you mean 'ray view'?"));
    r = runRay({chess, "640"});
    CHECK(r.exitCode == 2);
    CHECK_THAT(r.output, Contains("depth must be between 0 and 64, not 640"));
    CHECK_THAT(r.output, Contains("a lone number after the scene is the recursion depth"));
    r = runRay({chess, "--strict=yes"});
    CHECK(r.exitCode == 2);
    CHECK_THAT(r.output, Contains("--strict is a switch: it takes no value"));
    r = runRay({"view", chess, "--prot", "0"});
    CHECK(r.exitCode == 2);
    CHECK_THAT(r.output, Contains("did you mean --port?"));
    r = runRay({"explain", "--help"});
    CHECK(r.exitCode == 0);
    CHECK_THAT(r.output, !Contains("size_and_depth"));
    CHECK_THAT(r.output, Contains("--threshold"));
    r = runRay({"explain", chess, "1", "1", "32", "24", "--threshold", "0.1", "--aa", "off"});
    CHECK(r.exitCode == 0);
    CHECK_THAT(r.output, Contains("pixel (1, 1) of 32x24"));
    r = runRay({"explain", chess, "1", "1", "--json"});
    CHECK(r.exitCode == 2);
    CHECK_THAT(r.output, Contains("--json needs a value"));
    CHECK(ray::closestMatch("--shadow", {"--stats", "--no-shadows"}) == "--no-shadows");
    CHECK(ray::closestMatch("--sed", {"--seed", "--samples"}) == "--seed");
    CHECK(ray::closestMatch("--zzzzzz", {"--seed", "--samples"}).empty());
}

TEST_CASE("the option --dof picks the lens: course by default, or disk", "[cli][dof]") {
    using ray::DofMode;
    using ray::kUsageText;
    using ray::parseCommandLine;
    CHECK(parseCommandLine({"a.xml"}).settings.dofMode == DofMode::Course);
    CHECK(parseCommandLine({"a.xml", "--dof", "disk"}).settings.dofMode == DofMode::Disk);
    CHECK(parseCommandLine({"a.xml", "--dof", "disk", "--dof", "course"}).settings.dofMode == DofMode::Course);
    CHECK(parseCommandLine({"a.xml", "--dof", "disk"}).settings.depthOfField);
    CHECK_FALSE(parseCommandLine({"a.xml", "--no-dof"}).settings.depthOfField);
    CHECK_THROWS_WITH(parseCommandLine({"a.xml", "--dof", "pinhole"}), "--dof must be course or disk, not 'pinhole'");
    CHECK(std::string(kUsageText).find("--dof MODE") != std::string::npos);
}

// ---------------------------------------------------------------------------------------
// Outputs written by the one writer (core/atomic_file.h; issue 49): never over the scene,
// never into a folder, through links, keeping modes; refusals exit 2 before the render.

namespace {

fs::path scratchCopyOfScene(const std::string& folder, const std::string& name) {
    const fs::path dir = ray::test::outputDir() / "cli" / folder;
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::copy_file(ray::test::scenesDir() / name, dir / name);
    return dir / name;
}

}  // namespace

TEST_CASE("an output naming the scene is refused before rendering, the scene unchanged", "[cli][writer]") {
    const fs::path s = scratchCopyOfScene("output_is_scene", "shadows.xml");
    const std::string before = readText(s);
    fs::create_symlink(s.filename(), s.parent_path() / "link.json");
    // A size that would render for minutes on the reference renderer: a refusal after the
    // render would time out here.
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{s.string(), "8000", "6000", "--device", "ref", "--stats-json", s.string()},
          std::vector<std::string>{s.string(), "8000", "6000", "--device", "ref", "--stats-json",
                                   (s.parent_path() / "link.json").string()},
          std::vector<std::string>{s.string(), "8000", "6000", "--device", "ref", "-o", s.string()},
          std::vector<std::string>{"explain", s.string(), "1", "1", "--json", s.string()}}) {
        auto r = runRay(args, 60);
        INFO(r.output);
        CHECK(r.exitCode == 2);
        CHECK_THAT(r.output, Contains(s.parent_path().string()) && Contains("is the scene") &&
                                 Contains("Name another file"));
        CHECK(readText(s) == before);
        CHECK(fs::is_symlink(s.parent_path() / "link.json"));
    }
}

TEST_CASE("a folder as the output image is refused before rendering", "[cli][writer]") {
    const fs::path folder = freshOutput("folder.png");
    fs::create_directories(folder);
    auto r = runRay({scene("shadows.xml"), "8000", "6000", "--device", "ref", "-o", folder.string()}, 60);
    INFO(r.output);
    CHECK(r.exitCode == 2);
    CHECK_THAT(r.output, Contains(folder.string() + ": is a folder") && Contains("name a file in it"));
    CHECK(fs::is_directory(folder));
    r = runRay({scene("shadows.xml"), "8000", "6000", "--device", "ref", "--stats-json", folder.string()}, 60);
    CHECK(r.exitCode == 2);
    CHECK_THAT(r.output, Contains("is a folder"));
}

TEST_CASE("a read-only output is refused unless --replace-read-only, modes and links are kept", "[cli][writer]") {
    const fs::path dir = ray::test::outputDir() / "cli" / "read_only_output";
    fs::remove_all(dir);
    fs::create_directories(dir / "real");
    const fs::path json = dir / "real" / "stats.json";
    std::ofstream(json) << "old";
    fs::permissions(json, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
    fs::create_symlink("real/stats.json", dir / "stats.json");
    const std::vector<std::string> render = {scene("shadows.xml"), "8", "6", "--device", "ref", "--quiet",
                                             "-o", (dir / "out.png").string(), "--stats-json",
                                             (dir / "stats.json").string()};
    auto r = runRay(render);
    INFO(r.output);
    CHECK(r.exitCode == 2);
    CHECK_THAT(r.output, Contains("is read-only") && Contains("--replace-read-only"));
    CHECK(readText(json) == "old");
    CHECK_FALSE(fs::exists(dir / "out.png"));  // refused before the render

    std::vector<std::string> replace = render;
    replace.push_back("--replace-read-only");
    r = runRay(replace);
    CHECK(r.exitCode == 0);
    CHECK_THAT(readText(json), Contains("\"width\": 8"));
    CHECK(fs::is_symlink(dir / "stats.json"));
    CHECK((fs::status(json).permissions() & fs::perms::all) ==
          (fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read));

    // A private file stays private.
    fs::permissions(dir / "out.png", fs::perms::owner_read | fs::perms::owner_write);
    r = runRay({scene("shadows.xml"), "8", "6", "--device", "ref", "--quiet", "-o", (dir / "out.png").string()});
    CHECK(r.exitCode == 0);
    CHECK((fs::status(dir / "out.png").permissions() & fs::perms::all) ==
          (fs::perms::owner_read | fs::perms::owner_write));
}

TEST_CASE("ray --stats-json /dev/stdout prints the statistics", "[cli][writer]") {
    auto r = runRay({scene("shadows.xml"), "8", "6", "--device", "ref", "--quiet", "-o",
                     freshOutput("stdout_stats.png").string(), "--stats-json", "/dev/stdout"});
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK_THAT(r.output, Contains("\"width\": 8"));
}
