// Helpers shared by the tests: where the data is, and comparing images.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "app/cli.h"
#include "image/image.h"
#include "reference/reference_renderer.h"
#include "scene/scene_loader.h"

namespace ray::test {

// ../shared beside the checkout (or $RAY_SHARED_DIR); nullopt when absent.
inline std::optional<std::filesystem::path> sharedDir() {
    std::filesystem::path dir = RAY_TEST_SHARED_DIR;
    if (const char* env = std::getenv("RAY_SHARED_DIR")) dir = env;
    if (std::filesystem::is_directory(dir / "cs123")) return dir;
    return std::nullopt;
}

// The course corpus's scenes (shared / "cs123" / "scenes" / *.xml), sorted by name.
inline std::vector<std::filesystem::path> courseScenes(const std::filesystem::path& shared) {
    std::vector<std::filesystem::path> scenes;
    for (const auto& entry : std::filesystem::directory_iterator(shared / "cs123" / "scenes"))
        if (entry.path().extension() == ".xml") scenes.push_back(entry.path());
    std::sort(scenes.begin(), scenes.end());
    return scenes;
}

// The course scenes whose pixels cost a hundred times the others' (16 shadow rays an area
// light, each of up to 64 camera samples; dof: 25 lens rays a sample, past thousands of
// spheres): at 64×48 recursiveSpheres4_area alone took 44 s on the reference renderer, over
// half of the corpus test's time, and 15 s on PoCL. Tests that render the whole corpus for
// what is not a pixel's value (an outcome, two devices alike) render these at a quarter of
// their pixels; the kernel-versus-host corpus test shows that the smaller size still finds
// what it looks for.
inline bool isCostlyCourseScene(const std::string& fileName) {
    return fileName == "recursiveSpheres4_area.xml" || fileName == "shadow_test_area.xml" ||
           fileName == "dof-recursiveSpheres4.xml";
}

// Prints the marker CTest turns into a skip (tests/CMakeLists.txt).
inline void skip(const std::string& why) { std::cout << "SKIPPED: " << why << std::endl; }

// The folders the build compiled in, each of which the variable of the same name overrides:
// the GPU bundle (scripts/gpu_bundle.sh) runs these tests far from the checkout.
inline std::filesystem::path builtInOr(const char* variable, const char* builtIn) {
    const char* env = std::getenv(variable);
    return env && *env ? env : builtIn;
}
inline std::filesystem::path scenesDir() { return builtInOr("RAY_TEST_SCENES_DIR", RAY_TEST_SCENES_DIR); }
inline std::filesystem::path testDataDir() { return builtInOr("RAY_TEST_DATA_DIR", RAY_TEST_DATA_DIR); }
inline std::filesystem::path outputDir() {
    std::filesystem::path dir = builtInOr("RAY_TEST_OUTPUT_DIR", RAY_TEST_OUTPUT_DIR);
    std::filesystem::create_directories(dir);
    return dir;
}

struct ImageDifference {
    double fractionWithin = 0;  // pixels whose every channel differs by at most the tolerance
    double meanAbsError = 0;    // over all channels, in 8-bit levels
    int maxError = 0;           // in 8-bit levels
};

// Compares two images as the 8-bit values SPEC §4 writes (floor(255·clamp(c))).
inline ImageDifference compare8bit(const Image& a, const Image& b, int toleranceLevels) {
    ImageDifference d;
    if (a.width != b.width || a.height != b.height) return d;
    size_t within = 0, pixels = size_t(a.width) * size_t(a.height);
    double sum = 0;
    for (size_t p = 0; p < pixels; ++p) {
        int worst = 0;
        for (int c = 0; c < 3; ++c) {
            int e = std::abs(quantize8(a.rgb[p * 3 + c]) - quantize8(b.rgb[p * 3 + c]));
            worst = std::max(worst, e);
            sum += e;
        }
        d.maxError = std::max(d.maxError, worst);
        if (worst <= toleranceLevels) ++within;
    }
    d.fractionWithin = pixels ? double(within) / double(pixels) : 0;
    d.meanAbsError = pixels ? sum / double(pixels * 3) : 0;
    return d;
}

// |a − b| ×4 per channel in 8-bit levels, for looking at where two images differ.
inline Image differenceImage(const Image& a, const Image& b) {
    Image d(a.width, a.height);
    for (size_t i = 0; i < d.rgb.size() && i < b.rgb.size(); ++i)
        d.rgb[i] = std::min(1.0f, 4.0f * float(std::abs(quantize8(a.rgb[i]) - quantize8(b.rgb[i]))) / 255.0f);
    return d;
}

struct CommandResult {
    int exitCode = -1;    // -1: killed by a signal or the timeout
    bool timedOut = false;
    double seconds = 0;
    std::string output;   // stdout and stderr together
    long peakMemoryKiB = 0;  // the process's maximum resident set size
};

// Runs the `ray` binary with the arguments, killing it after timeoutSeconds.
inline CommandResult runRay(const std::vector<std::string>& args, double timeoutSeconds = 60,
                            const std::vector<std::string>& extraEnvironment = {}) {
    static int counter = 0;
    std::filesystem::path log = outputDir() / ("ray_output_" + std::to_string(getpid()) + "_" + std::to_string(counter++) + ".txt");
    std::vector<std::string> argvStrings{RAY_TEST_BINARY};
    argvStrings.insert(argvStrings.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : argvStrings) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::vector<std::string> envStrings;
    for (char** e = environ; *e; ++e) envStrings.emplace_back(*e);
    envStrings.insert(envStrings.end(), extraEnvironment.begin(), extraEnvironment.end());
    std::vector<char*> envp;
    for (auto& e : envStrings) envp.push_back(e.data());
    envp.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    pid_t pid = 0;
    CommandResult result;
    auto start = std::chrono::steady_clock::now();
    int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) return result;
    int status = 0;
    rusage usage{};
    while (true) {
        pid_t done = wait4(pid, &status, WNOHANG, &usage);
        result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (done == pid) break;
        if (result.seconds > timeoutSeconds) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            result.timedOut = true;
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (!result.timedOut && WIFEXITED(status)) result.exitCode = WEXITSTATUS(status);
    result.peakMemoryKiB = usage.ru_maxrss;
    std::ifstream in(log);
    result.output.assign(std::istreambuf_iterator<char>(in), {});
    std::filesystem::remove(log);
    return result;
}

// A row of ../shared/cs123/reference/INDEX.tsv: a course render and how to reproduce it.
struct ReferenceCase {
    std::string image;    // the course's render, in cs123/reference/
    std::string scene;    // relative to cs123/
    std::string options;  // ray's command-line options that match the course's settings
};

// Load options that print no warning (a test checks what it means to), with or without
// decoding the textures.
inline LoadOptions quietLoadOptions(bool loadImages = true) {
    LoadOptions options;
    options.warn = [](const std::string&) {};
    options.loadImages = loadImages;
    return options;
}

// A whole file as text, byte for byte (empty when it cannot be read).
inline std::string fileText(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// Writes `text` as the whole file, byte for byte.
inline void writeFileText(const std::filesystem::path& file, const std::string& text) {
    std::ofstream(file, std::ios::binary) << text;
}

// A text's lines, without their line ends.
inline std::vector<std::string> textLines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

// An empty folder of the tests' output, `outputDir()/group/name`, made anew.
inline std::filesystem::path freshOutputFolder(const std::string& group, const std::string& name) {
    const std::filesystem::path folder = outputDir() / group / name;
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    return folder;
}

// A small render for comparing scenes, not images: 64x48 on the reference renderer, one
// sample a pixel and one an area light (the course's antialiasing and 16 area samples cost
// four times as much for no more geometry, materials or lights seen).
inline Image renderSmallReference(const Scene& scene) {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.antialias = AntialiasMode::Off;
    settings.areaSamples = 1;
    ReferenceRenderOptions options;
    options.threads = 2;
    return renderReference(scene, settings, options);
}

// A whole file's bytes (empty when it cannot be read), for byte-for-byte comparisons.
inline std::vector<char> readFileBytes(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::vector<char>(std::istreambuf_iterator<char>(in), {});
}

inline std::vector<ReferenceCase> readReferenceIndex(const std::filesystem::path& indexFile) {
    std::vector<ReferenceCase> cases;
    std::ifstream in(indexFile);
    std::string line;
    std::getline(in, line);  // the header
    while (std::getline(in, line)) {
        std::vector<std::string> fields;
        std::stringstream columns(line);
        for (std::string field; std::getline(columns, field, '\t');) fields.push_back(field);
        if (fields.size() >= 4) cases.push_back({fields[0], fields[1], fields[3]});
    }
    return cases;
}

// Render settings from command-line option words, read by ray's own parser.
inline RenderSettings settingsFromOptions(const std::string& options, int width, int height, int depth = 4) {
    std::vector<std::string> args{"scene.xml", std::to_string(width), std::to_string(height), std::to_string(depth)};
    std::stringstream words(options);
    for (std::string word; words >> word;) args.push_back(word);
    return parseCommandLine(args).settings;
}

}  // namespace ray::test
