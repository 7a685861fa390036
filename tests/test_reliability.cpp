// Hostile input, resource limits and interruption (issue 6): every case either renders or
// is refused before work starts with a message naming the limit, and nothing already on
// disk is lost.
#include <catch2/catch.hpp>

#include <atomic>
#include <fstream>

#include "devices/renderer.h"
#include "kernel_comparison.h"
#include "opencl/opencl_renderer.h"
#include "reference/reference_renderer.h"
#include "render/tile_side.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using ray::test::outputDir;
using ray::test::runRay;

void writeText(const fs::path& file, const std::string& text) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out << text;
}

std::string readText(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

const std::string kSphere = R"(<object type="primitive" name="sphere"><diffuse r="1" g="0.2" b="0.2"/></object>)";

// Trees m0 .. m<levels>, m<i> holding `fanOut` instances of m<i-1>; root holds m<levels>:
// fanOut^levels spheres.
std::string masterScene(int levels, int fanOut) {
    std::string xml = "<scenefile>\n<object type=\"tree\" name=\"m0\"><transblock>" + kSphere + "</transblock></object>\n";
    for (int i = 1; i <= levels; ++i) {
        xml += "<object type=\"tree\" name=\"m" + std::to_string(i) + "\">";
        for (int k = 0; k < fanOut; ++k)
            xml += "<transblock><translate x=\"" + std::to_string(k) + "\" y=\"0\" z=\"0\"/><object type=\"master\" name=\"m" +
                   std::to_string(i - 1) + "\"/></transblock>";
        xml += "</object>\n";
    }
    return xml + "<object type=\"tree\" name=\"root\"><transblock><object type=\"master\" name=\"m" +
           std::to_string(levels) + "\"/></transblock></object>\n</scenefile>\n";
}

fs::path writeScene(const std::string& name, const std::string& xml) {
    fs::path file = outputDir() / name;
    writeText(file, xml);
    return file;
}

// A file that must survive a refused or interrupted render unchanged.
fs::path existingOutput(const std::string& name) {
    fs::path file = outputDir() / name;
    writeText(file, "an earlier render");
    return file;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Starts `ray` with the arguments, sends `signal` after `delaySeconds`, and waits for it.
struct Interrupted {
    int exitCode = -1;
    double secondsAfterSignal = 0;
};

Interrupted interruptRay(const std::vector<std::string>& args, double delaySeconds, int signal) {
    std::vector<std::string> argvStrings{RAY_TEST_BINARY};
    argvStrings.insert(argvStrings.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : argvStrings) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    pid_t pid = 0;
    Interrupted result;
    int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    REQUIRE(rc == 0);
    // The reference renderer starts its worker threads when the render begins: a loaded
    // machine can take over a second to get there (then the signal would only test the
    // exit before rendering). One core means no workers: the timer alone then.
    auto started = std::chrono::steady_clock::now();
    auto threads = [&] {
        size_t count = 0;
        std::error_code ec;
        for (fs::directory_iterator it("/proc/" + std::to_string(pid) + "/task", ec), end; !ec && it != end; ++it) ++count;
        return count;
    };
    while (threads() < 2 && std::chrono::steady_clock::now() - started < std::chrono::seconds(20))
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    std::this_thread::sleep_for(std::chrono::duration<double>(delaySeconds));
    auto signalled = std::chrono::steady_clock::now();
    kill(pid, signal);
    int status = 0;
    while (waitpid(pid, &status, WNOHANG) != pid) {
        result.secondsAfterSignal = std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
        if (result.secondsAfterSignal > 30) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            return result;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (WIFEXITED(status)) result.exitCode = WEXITSTATUS(status);
    return result;
}

// Minutes of work on the reference renderer if left alone (no kernel compile to wait for).
std::vector<std::string> slowRender(const fs::path& output) {
    return {(ray::test::scenesDir() / "reflection_depth.xml").string(), "1200", "900", "8", "--device", "ref",
            "--aa", "stratified", "--samples", "1024", "--quiet", "-o", output.string()};
}

}  // namespace

TEST_CASE("Ctrl-C stops a long render within a second, exits 130 and leaves the output untouched", "[reliability]") {
    fs::path output = existingOutput("interrupted.png");
    Interrupted run = interruptRay(slowRender(output), 0.5, SIGINT);
    INFO("stopped " << run.secondsAfterSignal << " s after SIGINT");
    CHECK(run.exitCode == 130);
    CHECK(run.secondsAfterSignal < 1.5);
    CHECK(readText(output) == "an earlier render");
}

TEST_CASE("SIGTERM with --partial writes the part rendered so far and exits 143", "[reliability]") {
    fs::path output = outputDir() / "partial.png";
    fs::remove(output);
    auto args = slowRender(output);
    args.push_back("--partial");
    Interrupted run = interruptRay(args, 0.5, SIGTERM);
    INFO("stopped " << run.secondsAfterSignal << " s after SIGTERM");
    CHECK(run.exitCode == 143);
    CHECK(run.secondsAfterSignal < 2.0);  // includes writing the PNG
    ray::Image partial = ray::readImage(output);
    CHECK(partial.width == 1200);
    CHECK(partial.height == 900);
}

TEST_CASE("A cancelled OpenCL render returns the tiles launched and black elsewhere", "[reliability][kernel]") {
    auto device = ray::test::cpuDevice();
    if (!device) return ray::test::skip("no OpenCL CPU device");
    ray::Scene scene = ray::loadScene(ray::test::scenesDir() / "shadows.xml");
    ray::RenderSettings settings = ray::test::settingsFromOptions("--aa off", 256, 256, 2);
    std::atomic<bool> cancel{false};
    ray::OpenClRenderOptions options;
    options.tileSize = 64;  // 16 tiles; cancelled when the first is done
    options.cancel = &cancel;
    options.progress = [&](double) { cancel = true; };
    ray::Image image = ray::renderOpenCl(*device, scene, settings, options, nullptr);
    REQUIRE(image.width == 256);
    // The last tile (bottom right) cannot have been launched: a few tiles are queued ahead
    // of the first one waited for, far fewer than 16.
    for (int y = 192; y < 256; ++y)
        for (int x = 192; x < 256; ++x) REQUIRE(image.at(x, y).x == 0);
    for (float v : image.rgb) REQUIRE(std::isfinite(v));
}

// The tiles queued when a render is cancelled must finish within about a second, so a
// tile holds fewer pixels the more rays each pixel traces: more samples, and the k² shadow
// rays an area light adds to every sample.
TEST_CASE("Cancellable tiles shrink with the samples and with area-light shadow rays", "[reliability]") {
    ray::Scene pointLit = ray::loadScene(ray::test::scenesDir() / "shadows.xml");
    ray::Scene areaLit = ray::loadScene(ray::test::scenesDir() / "light_area.xml");
    auto side = [](const ray::Scene& scene, const char* options) {
        return ray::cancellableTileSize(ray::test::settingsFromOptions(options, 64, 64), scene);
    };
    CHECK(side(pointLit, "--aa off") == ray::kDefaultTileSide);  // an uncancellable frame's
    CHECK(side(pointLit, "") == 40);  // the course's up to 64 samples
    CHECK(side(pointLit, "--aa stratified --samples 4096") == 8);
    // 16 area samples: 17 rays a sample against the 2.5 the tiles were measured with
    CHECK(side(areaLit, "") < side(pointLit, ""));
    CHECK(side(pointLit, "--aa stratified --samples 64") == 40);
    CHECK(side(areaLit, "--aa stratified --samples 64") == 16);
    CHECK(side(areaLit, "--area-samples 1024") == 8);
    CHECK(side(areaLit, "--area-samples 16") > side(areaLit, "--area-samples 256"));
}

TEST_CASE("Limits: an image too big for memory is refused before rendering, with exit 2", "[reliability]") {
    fs::path output = existingOutput("too_big.png");
    auto run = runRay({(ray::test::scenesDir() / "shadows.xml").string(), "16384", "16384", "--device", "ref", "-o",
                       output.string()},
                      60, {"RAY_MEMORY_LIMIT=256M"});
    INFO(run.output);
    CHECK(run.exitCode == 2);
    CHECK(contains(run.output, "16384x16384 image needs about"));
    CHECK(contains(run.output, "render a smaller image"));
    CHECK(run.seconds < 10);
    CHECK(readText(output) == "an earlier render");
}

TEST_CASE("Limits: out-of-range sizes, depths and sample counts are usage errors", "[reliability]") {
    const std::string scene = (ray::test::scenesDir() / "shadows.xml").string();
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {scene, "16385", "10"}, {scene, "10", "0"}, {scene, "10", "10", "65"}, {scene, "10", "10", "-1"},
             {scene, "--aa", "stratified", "--samples", "4097"}, {scene, "--max-primitives", "0"},
             {scene, "99999999999999999999", "10"}}) {
        auto run = runRay(args);
        INFO(run.output);
        CHECK(run.exitCode == 2);
        CHECK(contains(run.output, "must be"));
    }
}

TEST_CASE("Limits: the deepest and most sampled render allowed still works", "[reliability]") {
    fs::path output = outputDir() / "deep_many_samples.png";
    auto run = runRay({(ray::test::scenesDir() / "reflection_depth.xml").string(), "2", "2", "64", "--device", "ref",
                       "--aa", "stratified", "--samples", "4096", "--quiet", "-o", output.string()});
    INFO(run.output);
    CHECK(run.exitCode == 0);
    CHECK(fs::exists(output));
}

TEST_CASE("Limits: exponentially instanced masters are refused before flattening", "[reliability]") {
    // 10^11 spheres from 12 small trees: counted, never made.
    fs::path scene = writeScene("exponential_masters.xml", masterScene(11, 10));
    auto run = runRay({scene.string(), "8", "6", "--device", "ref", "-o", (outputDir() / "exp.png").string()});
    INFO(run.output);
    CHECK(run.exitCode == 2);
    CHECK(contains(run.output, "flattens to 100000000000 primitive instances, more than the limit of 50000000"));
    CHECK(contains(run.output, "--max-primitives"));
    CHECK(run.seconds < 10);

    auto limited = runRay({writeScene("masters_1000.xml", masterScene(3, 10)).string(), "8", "6", "--device", "ref",
                           "--max-primitives", "999", "-o", (outputDir() / "exp.png").string()});
    CHECK(limited.exitCode == 2);
    CHECK(contains(limited.output, "1000 primitive instances, more than the limit of 999"));
}

TEST_CASE("Limits: primitives that would not fit in memory are refused before flattening", "[reliability]") {
    // 10^6 spheres need ~600 MiB; with 64 MiB allowed the count alone refuses them.
    fs::path scene = writeScene("million_spheres.xml", masterScene(6, 10));
    auto run = runRay({scene.string(), "8", "6", "--device", "ref", "-o", (outputDir() / "million.png").string()}, 60,
                      {"RAY_MEMORY_LIMIT=64M"});
    INFO(run.output);
    CHECK(run.exitCode == 2);
    CHECK(contains(run.output, "1000000 primitive instances, which needs about"));
    CHECK(contains(run.output, "RAY_MEMORY_LIMIT"));
}

TEST_CASE("Limits: masters nested 100000 deep are refused, 999 deep render", "[reliability]") {
    auto chain = [](int length) {
        std::string xml = "<scenefile>\n<object type=\"tree\" name=\"m0\"><transblock>" + kSphere + "</transblock></object>\n";
        for (int i = 1; i < length; ++i)
            xml += "<object type=\"tree\" name=\"m" + std::to_string(i) + "\"><transblock><object type=\"master\" name=\"m" +
                   std::to_string(i - 1) + "\"/></transblock></object>\n";
        return xml + "<object type=\"tree\" name=\"root\"><transblock><object type=\"master\" name=\"m" +
               std::to_string(length - 1) + "\"/></transblock></object>\n</scenefile>\n";
    };
    ray::LoadOptions options;
    options.warn = [](const std::string&) {};
    // Overflowed the stack (a crash) before the nesting limit.
    CHECK_THROWS_WITH(ray::loadSceneFromText(chain(100000), "chain.xml", options),
                      Catch::Contains("nest more than 1000 levels deep"));
    CHECK(ray::loadSceneFromText(chain(999), "chain.xml", options).primitives.size() == 1);

    // Inline trees: 999 levels below the root load, one more is the nesting rule's error,
    // and 20000 levels (40000 elements deep) stop at the XML tree's depth limit, before the
    // parser's recursion could exhaust the stack.
    auto nested = [](int levels) {
        std::string xml = "<scenefile><object type=\"tree\" name=\"root\">";
        for (int i = 0; i < levels; ++i) xml += "<transblock><object type=\"tree\">";
        xml += "<transblock>" + kSphere + "</transblock>";
        for (int i = 0; i < levels; ++i) xml += "</object></transblock>";
        return xml + "</object></scenefile>";
    };
    CHECK(ray::loadSceneFromText(nested(999), "nested.xml", options).primitives.size() == 1);
    CHECK_THROWS_WITH(ray::loadSceneFromText(nested(1000), "nested.xml", options),
                      Catch::Contains("nest more than 1000 levels deep"));
    CHECK_THROWS_WITH(ray::loadSceneFromText(nested(20000), "nested.xml", options),
                      Catch::Contains("nested.xml:1: error: elements nest more than 2008 levels deep"));
}

TEST_CASE("Limits: huge, truncated and bogus textures leave the surface its colors", "[reliability]") {
    fs::path folder = outputDir() / "bad_textures";
    fs::create_directories(folder);
    // A PNG header claiming 65535 x 65535 pixels (68 bytes).
    fs::copy_file(ray::test::testDataDir() / "limits" / "huge_header.png", folder / "huge.png",
                  fs::copy_options::overwrite_existing);
    // 1 KB claiming a 1.9 GB text chunk: took 10 s and 2 GB inside libpng before it was refused.
    fs::copy_file(ray::test::testDataDir() / "fuzz" / "image_reader" / "png_chunk_claims_2gb.png",
                  folder / "chunk.png", fs::copy_options::overwrite_existing);
    // 40 bytes whose GIF screen claims 15000 x 15000: OpenImageIO allocated 900 MB opening it.
    fs::copy_file(ray::test::testDataDir() / "fuzz" / "image_reader" / "gif_screen_claims_15000x15000.gif",
                  folder / "screen.gif", fs::copy_options::overwrite_existing);
    std::string grid = readText(ray::test::scenesDir() / "textures" / "uvgrid.png");
    writeText(folder / "truncated.png", grid.substr(0, grid.size() / 2));
    writeText(folder / "empty.png", "");
    writeText(folder / "text.png", "not an image at all");
    writeText(folder / "huge.ppm", "P6\n100000 100000\n255\n\x01\x02\x03");
    const std::pair<const char*, const char*> cases[] = {{"huge.png", "more than a texture's budget"},
                                                         {"truncated.png", "cannot"},
                                                         {"empty.png", "cannot read image"},
                                                         {"text.png", "cannot read image"},
                                                         {"huge.ppm", "cannot read image"},
                                                         {"chunk.png", "corrupt PNG: its tEXt chunk claims"},
                                                         {"screen.gif", "claims 15000 × 15000 pixels"}};
    for (const auto& [texture, message] : cases) {
        fs::path scene = writeScene("bad_textures/scene.xml",
                                    std::string("<scenefile><object type=\"tree\" name=\"root\"><transblock>"
                                                "<object type=\"primitive\" name=\"sphere\"><diffuse r=\"1\" g=\"0\" b=\"0\"/>"
                                                "<texture file=\"") +
                                        texture + "\"/></object></transblock></object></scenefile>");
        fs::path output = folder / "out.png";
        auto run = runRay({scene.string(), "8", "6", "--device", "ref", "-o", output.string()});
        INFO(texture << ": " << run.output);
        CHECK(run.exitCode == 0);
        CHECK(run.seconds < 30);  // a hang guard: sanitizer builds on a busy machine take ~8 s
        CHECK(contains(run.output, "warning: cannot read image"));
        CHECK(contains(run.output, message));
        auto strict = runRay({scene.string(), "8", "6", "--device", "ref", "--strict", "-o", output.string()});
        CHECK(strict.exitCode == 2);
    }
}

// Inputs the fuzzers (fuzz/, scripts/fuzz.sh) found crashing, kept so they stay fixed: each
// loads to a scene or a clean InputError / ImageError.
TEST_CASE("Fuzzer regressions: scene files", "[reliability][fuzz]") {
    fs::path folder = ray::test::testDataDir() / "fuzz" / "scene_loader";
    if (!fs::is_directory(folder)) return ray::test::skip("no scene inputs kept yet");
    ray::LoadOptions options;
    options.warn = [](const std::string&) {};
    options.maxPrimitives = 20000;
    for (const auto& entry : fs::directory_iterator(folder)) {
        INFO(entry.path());
        try {
            ray::Scene scene = ray::loadScene(entry.path(), options);
            ray::RenderSettings settings = ray::test::settingsFromOptions("--aa off", 4, 3, 2);
            ray::renderReference(scene, settings);
        } catch (const ray::InputError&) {
        }
    }
}

TEST_CASE("Fuzzer regressions: textures", "[reliability][fuzz]") {
    fs::path folder = ray::test::testDataDir() / "fuzz" / "image_reader";
    if (!fs::is_directory(folder)) return ray::test::skip("no texture inputs kept yet");
    for (const auto& entry : fs::directory_iterator(folder)) {
        INFO(entry.path());
        auto start = std::chrono::steady_clock::now();
        try {
            ray::readImage(entry.path());
        } catch (const ray::ImageError&) {
        }
        CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 2);
    }
}
