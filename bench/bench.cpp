// ray_bench: renders a fixed set of scenes with `ray` on every OpenCL device and on the host
// reference renderer, and reports speed, ray counts, build times and memory side by side.
// See bench/README.md. Not a test: nothing here runs under CTest.
#include <unistd.h>

#include <CLI/CLI.hpp>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "child_process.h"
#include "mesh_scenes.h"
#include "primitive_count.h"
#include "ray_runs.h"
#include "report.h"
#include "sphere_scenes.h"

namespace {

namespace fs = std::filesystem;
using namespace bench;
using Clock = std::chrono::steady_clock;

const char* const kUsage = R"(usage: ray_bench [options]

Renders chess, recursiveSpheres10, ray_killer, recursiveCones4 (from the course corpus)
and generated scenes of 10^2..10^6 spheres with `ray --aa off`, depth 4, on each OpenCL
device (a cold then a warm kernel cache) and on the reference renderer; prints a table
and writes JSON.

options:
  --quick               256x192 instead of 1024x768 (a smoke run of a minute or two)
  --out FILE            JSON results (default: bench/results.json in the source tree)
  --scenes DIR          the course's scenes folder (default: ../shared/cs123/scenes beside
                        the checkout, or $RAY_SHARED_DIR/cs123/scenes)
  --ray PATH            the ray binary (default: ../ray next to this program)
  --ref-timeout S       kill a reference run after S seconds (default 120)
  --ref-max-prims N     run the reference only on scenes of at most N primitives
                        (default 10000000)
  --plain-max-prims N   also run the plain reference (ray --device ref --no-bvh: every
                        primitive tested for every ray) on the corpus and sphere scenes
                        of at most N primitives (default 1000; 0: never)
  --keep                keep the temporary folder (scenes, logs, statistics)
  --write-scenes DIR    only write the generated sphere scenes into DIR, then exit
  --meshes              only the mesh rows: generated UV spheres of 10^3..10^6 triangles
                        and the course's three meshes (frostmourne, pdiddy, xyzrgb_dragon)
  --features            only the feature rows: bundled scenes of spot and area lights,
                        refraction, depth of field, the antialiasing modes and motion
                        blur, each
                        beside the plain scene it extends (see bench/README.md)
  -h, --help            this text
)";

constexpr const char* kCorpusScenes[] = {"chess", "recursiveSpheres10", "ray_killer", "recursiveCones4"};
constexpr int kFewestSphereLevels = 2;  // 10^2 spheres
constexpr int kMostSphereLevels = 6;    // 10^6 spheres
// OpenCL runs get a limit too, only so that a hung driver cannot hang the bench.
constexpr double kOpenClTimeoutSeconds = 600;

struct BenchOptions {
    bool quick = false;
    bool featuresOnly = false;  // --features
    bool meshesOnly = false;    // --meshes
    bool keep = false;
    fs::path out = fs::path(BENCH_SOURCE_DIR) / "results.json";
    fs::path scenesDir;
    fs::path rayBinary;
    fs::path writeScenesTo;  // --write-scenes: generate, run nothing
    double referenceTimeoutSeconds = 120;
    uint64_t referenceMaxPrimitives = 10'000'000;
    uint64_t plainMaxPrimitives = 1000;
};

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

fs::path defaultScenesDir() {
    if (const char* shared = std::getenv("RAY_SHARED_DIR"); shared && *shared)
        return fs::path(shared) / "cs123" / "scenes";
    return fs::path(RAY_SOURCE_DIR) / ".." / "shared" / "cs123" / "scenes";
}

// ray_bench lives in <build>/bench/, ray in <build>/.
fs::path defaultRayBinary() {
    return fs::read_symlink("/proc/self/exe").parent_path().parent_path() / "ray";
}

// The options, parsed by CLI11 (as the ray command's are); kUsage is the help text.
BenchOptions parseOptions(int argc, char** argv) {
    BenchOptions options;
    CLI::App app("ray_bench", "ray_bench");
    app.set_help_flag();  // -h prints kUsage below
    bool help = false;
    app.add_flag("-h,--help", help);
    app.add_flag("--quick", options.quick);
    app.add_flag("--keep", options.keep);
    app.add_flag("--features", options.featuresOnly);
    app.add_flag("--meshes", options.meshesOnly);
    app.add_option("--out", options.out);
    app.add_option("--scenes", options.scenesDir);
    app.add_option("--ray", options.rayBinary);
    app.add_option("--write-scenes", options.writeScenesTo);
    app.add_option("--ref-timeout", options.referenceTimeoutSeconds)->check(CLI::Range(0.0, 1e6));  // seconds
    app.add_option("--ref-max-prims", options.referenceMaxPrimitives);
    app.add_option("--plain-max-prims", options.plainMaxPrimitives);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        throw UsageError(e.what());
    }
    if (help) {
        std::cout << kUsage;
        std::exit(0);
    }
    if (options.scenesDir.empty()) options.scenesDir = defaultScenesDir();
    if (options.rayBinary.empty()) options.rayBinary = defaultRayBinary();
    return options;
}

fs::path makeTemporaryFolder() {
    std::string pattern = (fs::temp_directory_path() / "ray_bench.XXXXXX").string();
    if (!mkdtemp(pattern.data()))
        throw std::runtime_error("cannot make a temporary folder: " + std::string(std::strerror(errno)));
    return pattern;
}

void addCorpusScenes(const fs::path& scenesDir, std::vector<BenchScene>& scenes) {
    if (!fs::is_directory(scenesDir)) {
        std::cerr << "ray_bench: no course scenes at " << scenesDir.string()
                  << " (give --scenes DIR); running the generated scenes only\n";
        return;
    }
    for (const char* name : kCorpusScenes) {
        fs::path file = scenesDir / (std::string(name) + ".xml");
        if (!fs::exists(file)) {
            std::cerr << "ray_bench: skipping " << name << ": " << file.string() << " is absent\n";
            continue;
        }
        scenes.push_back({name, file, countPrimitives(file), 0, {}, true});
    }
}

// The feature rows (issue 4): each a bundled scene with the options that switch the
// feature on, next to the plain scene or setting it is measured against.
void addFeatureScenes(std::vector<BenchScene>& scenes) {
    const fs::path bundled = fs::path(RAY_SOURCE_DIR) / "scenes";
    struct Feature {
        const char* name;
        const char* file;
        std::vector<std::string> options;
    };
    const Feature features[] = {
        {"plain_shadows", "shadows.xml", {"--aa", "off"}},
        {"spot_light", "light_spot.xml", {"--aa", "off"}},
        {"area_light_16", "light_area.xml", {"--aa", "off"}},
        {"area_light_64", "light_area.xml", {"--aa", "off", "--area-samples", "64"}},
        {"refraction_off", "refraction.xml", {"--aa", "off", "--no-refraction"}},
        {"refraction", "refraction.xml", {"--aa", "off"}},
        {"dof_off", "depth_of_field.xml", {"--aa", "off", "--no-dof"}},
        {"dof_16", "depth_of_field.xml", {"--aa", "stratified", "--samples", "16", "--dof", "disk"}},
        {"aa_course", "shadows.xml", {"--aa", "course"}},
        {"aa_stratified_16", "shadows.xml", {"--aa", "stratified", "--samples", "16"}},
        {"aa_adaptive_16", "shadows.xml", {"--aa", "adaptive", "--samples", "16"}},
        {"motion_off", "motion_blur.xml", {"--aa", "stratified", "--samples", "16", "--shutter", "0"}},
        {"motion_16", "motion_blur.xml", {"--aa", "stratified", "--samples", "16"}},
    };
    for (const Feature& f : features) {
        fs::path file = bundled / f.file;
        if (!fs::exists(file)) {
            std::cerr << "ray_bench: skipping " << f.name << ": " << file.string() << " is absent\n";
            continue;
        }
        scenes.push_back({f.name, file, countPrimitives(file), 0, f.options});
    }
}

// The mesh rows (issue 5): UV spheres of 10^3..10^6 triangles, one mesh each (the
// scaling of the per-mesh BVH: its build seconds, Mrays/s and peak memory), then the
// course's three models: frostmourne.xml and pdiddy.xml (monsterdance.obj) as the course
// has them, xyzrgb_dragon.obj (in no course scene) alone in a scene written here.
void addMeshScenes(const fs::path& scenesDir, const fs::path& folder, std::vector<BenchScene>& scenes) {
    for (int power = 3; power <= 6; ++power) {
        std::string name = "uvsphere_1e" + std::to_string(power);
        fs::path file = folder / (name + ".xml");
        uint64_t triangles = writeUvSphereScene(file, folder / (name + ".obj"), uint64_t(std::pow(10.0, power)));
        std::cerr << "ray_bench: " << name << " has " << triangles << " triangles\n";
        scenes.push_back({name, file, countPrimitives(file), 0, {}});
    }
    for (const char* name : {"frostmourne", "pdiddy"}) {
        fs::path file = scenesDir / (std::string(name) + ".xml");
        if (!fs::exists(file)) {
            std::cerr << "ray_bench: skipping " << name << ": " << file.string() << " is absent\n";
            continue;
        }
        scenes.push_back({name, file, countPrimitives(file), 0, {}});
    }
    fs::path dragon = scenesDir.parent_path() / "mesh" / "xyzrgb_dragon.obj";
    if (!fs::exists(dragon)) {
        std::cerr << "ray_bench: skipping xyzrgb_dragon: " << dragon.string() << " is absent\n";
        return;
    }
    fs::path file = folder / "xyzrgb_dragon.xml";
    writeSingleMeshScene(file, dragon);
    scenes.push_back({"xyzrgb_dragon", file, countPrimitives(file), 0, {}});
}

void addSphereScenes(const fs::path& folder, std::vector<BenchScene>& scenes) {
    for (int levels = kFewestSphereLevels; levels <= kMostSphereLevels; ++levels) {
        std::string name = "spheres_1e" + std::to_string(levels);
        fs::path file = folder / (name + ".xml");
        writeSphereScene(file, levels);
        scenes.push_back({name, file, countPrimitives(file), levels, {}, true});
    }
}

std::string primitivesText(const BenchScene& scene) {
    return scene.primitives ? std::to_string(*scene.primitives) : "?";
}

// The reference renderer has a BVH of its own, so it is fast enough for every scene here
// (10^6 spheres at 1024x768 in seconds); the cap only spares it scenes whose
// double-precision copy would not fit in memory, and the time limit catches the rest.
//
// The plain reference (no BVH) costs primitives × rays, so it gets only the corpus and
// sphere scenes that are small enough: it is there to time the kernel against the oracle
// in its simplest form, not to cover every row.
bool referenceShouldRun(const BenchScene& scene, const BenchDevice& device, const BenchOptions& options,
                        std::string& whyNot) {
    if (device.isPlainReference()) {
        if (!scene.plainReference) {
            whyNot = "not run (the plain reference runs on the corpus and sphere scenes)";
            return false;
        }
        if (scene.primitives && *scene.primitives <= options.plainMaxPrimitives) return true;
        whyNot = "skipped (" + primitivesText(scene) + " prims > " + std::to_string(options.plainMaxPrimitives) +
                 ", --plain-max-prims)";
        return false;
    }
    if (!scene.primitives || *scene.primitives <= options.referenceMaxPrimitives) return true;
    whyNot = "skipped (" + std::to_string(*scene.primitives) + " prims > " +
             std::to_string(options.referenceMaxPrimitives) + ")";
    return false;
}

class BenchRunner {
public:
    BenchRunner(const BenchOptions& options, const fs::path& workDir, BenchResults& results)
        : options_(options), workDir_(workDir), results_(results) {}

    void runAll() {
        size_t total = countPlannedRuns();
        for (const BenchScene& scene : results_.scenes)
            for (const BenchDevice& device : results_.devices) {
                if (device.isReference()) runReference(scene, device, total);
                else runOpenCl(scene, device, total);
            }
    }

private:
    size_t countPlannedRuns() const {
        size_t runs = 0;  // skipped reference runs count too: each is a line of the log
        for (const BenchDevice& device : results_.devices) runs += device.isReference() ? 1 : 2;
        return results_.scenes.size() * runs;
    }

    RayInvocation invocation(const fs::path& cacheDir, double timeoutSeconds) const {
        return {options_.rayBinary, workDir_, cacheDir, results_.size, timeoutSeconds};
    }

    // Cold, then warm with the same (now filled) caches.
    void runOpenCl(const BenchScene& scene, const BenchDevice& device, size_t total) {
        fs::path cacheDir = workDir_ / ("cache." + scene.name + "." + device.label);
        fs::remove_all(cacheDir);
        fs::create_directories(cacheDir);
        for (Phase phase : {Phase::Cold, Phase::Warm})
            record(runRay(invocation(cacheDir, kOpenClTimeoutSeconds), scene, device, phase), total);
    }

    void runReference(const BenchScene& scene, const BenchDevice& device, size_t total) {
        std::string whyNot;
        if (referenceShouldRun(scene, device, options_, whyNot)) {
            RayInvocation limited = invocation({}, options_.referenceTimeoutSeconds);
            record(runRay(limited, scene, device, Phase::Reference), total);
            return;
        }
        RunRecord skipped;
        skipped.scene = &scene;
        skipped.device = &device;
        skipped.status = whyNot;
        record(skipped, total);
    }

    void record(const RunRecord& run, size_t total) {
        results_.runs.push_back(run);
        std::cerr << "[" << results_.runs.size() << "/" << total << "] " << run.scene->name << " on "
                  << run.device->label << " (" << phaseName(run.phase) << "): ";
        if (run.ok())
            std::cerr << "render " << run.stats->renderSeconds << " s, wall " << run.wallSeconds << " s\n";
        else
            std::cerr << run.status << "\n";
    }

    const BenchOptions& options_;
    fs::path workDir_;
    BenchResults& results_;
};

// The bench runs a private copy of `ray`, so that a rebuild of the original while it runs
// (the kernel is embedded in the binary) can neither fail a run halfway through the set nor
// make a warm run miss the cache its cold run filled. A copy taken mid-link fails to run;
// then it is taken again.
fs::path snapshotRayBinary(const fs::path& original, const fs::path& workDir) {
    const fs::path copy = workDir / "ray";
    constexpr int kAttempts = 30;
    for (int attempt = 1; attempt <= kAttempts; ++attempt) {
        std::error_code error;
        fs::copy_file(original, copy, fs::copy_options::overwrite_existing, error);
        if (!error) {
            ChildCommand version;
            version.argv = {copy.string(), "--version"};
            version.log = workDir / "version.txt";
            version.timeoutSeconds = 30;
            if (runChild(version).succeeded()) return copy;
        }
        std::this_thread::sleep_for(std::chrono::seconds(2));
    }
    throw std::runtime_error("cannot take a working copy of " + original.string());
}

BenchResults prepareResults(const BenchOptions& options, const fs::path& workDir) {
    BenchResults results;
    if (options.quick) results.size = {256, 192, 4};
    results.quick = options.quick;
    results.rayBinary = options.rayBinary.string();
    results.scenesDir = options.scenesDir.string();
    results.referenceTimeoutSeconds = options.referenceTimeoutSeconds;
    results.referenceMaxPrimitives = options.referenceMaxPrimitives;
    fs::path generated = workDir / "scenes";
    fs::create_directories(generated);
    if (!options.featuresOnly && !options.meshesOnly) {
        addCorpusScenes(options.scenesDir, results.scenes);
        addSphereScenes(generated, results.scenes);
    }
    if (!options.featuresOnly) addMeshScenes(options.scenesDir, generated, results.scenes);
    if (!options.meshesOnly) addFeatureScenes(results.scenes);
    results.devices = listOpenClDevices(options.rayBinary, workDir);
    results.devices.push_back({"ref", "ref", "the host reference renderer", {}});
    if (options.plainMaxPrimitives > 0)
        results.devices.push_back({"ref", "plain", "the host reference renderer without its BVH (--no-bvh)", {"--no-bvh"}});
    results.plainMaxPrimitives = options.plainMaxPrimitives;
    return results;
}

int runBench(BenchOptions options) {
    if (access(options.rayBinary.c_str(), X_OK) != 0)
        throw UsageError("no ray binary at " + options.rayBinary.string() + " (build it, or give --ray PATH)");
    auto start = Clock::now();
    const fs::path workDir = makeTemporaryFolder();
    const fs::path originalRay = options.rayBinary;
    options.rayBinary = snapshotRayBinary(originalRay, workDir);
    BenchResults results = prepareResults(options, workDir);
    results.rayBinary = originalRay.string();
    BenchRunner(options, workDir, results).runAll();
    results.totalWallSeconds = std::chrono::duration<double>(Clock::now() - start).count();

    printRunTable(results, std::cout);
    printSphereScaling(results, std::cout);
    writeResultsJson(results, options.out);
    std::cout << "\nwrote " << options.out.string() << "\n";
    if (options.keep) std::cout << "kept " << workDir.string() << "\n";
    else fs::remove_all(workDir);
    return 0;
}

int writeScenesOnly(const fs::path& folder) {
    fs::create_directories(folder);
    std::vector<BenchScene> scenes;
    addSphereScenes(folder, scenes);
    for (const BenchScene& scene : scenes)
        std::cout << scene.file.string() << ": " << primitivesText(scene) << " primitives\n";
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        BenchOptions options = parseOptions(argc, argv);
        if (!options.writeScenesTo.empty()) return writeScenesOnly(options.writeScenesTo);
        return runBench(options);
    } catch (const UsageError& e) {
        std::cerr << "ray_bench: " << e.what() << "\n(see ray_bench --help)\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "ray_bench: " << e.what() << "\n";
        return 1;
    }
}
