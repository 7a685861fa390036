// ray: renders a CS123 scenefile. See `ray --help` and README.md.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <string_view>
#include <vector>

#include "app/cli.h"
#include "app/convert_command.h"
#include "app/command_modules.h"
#include "app/progress.h"
#include "app/render_command.h"
#include "app/mpi_launch.h"
#include "core/huge_pages.h"
#include "core/memory_limits.h"
#include "devices/renderer.h"
#include "explain/explain_command.h"

namespace {

using namespace ray;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

void printHelp();

// --stats's memory line: the peak so far (the frame is done) and the meshes' triangles.
void recordMemory(const Scene& scene, RenderStats& stats) {
    stats.peakMemoryBytes = peakResidentBytes();
    for (const TriangleMesh& mesh : scene.meshes) {
        stats.meshTriangles += mesh.triangles.size();
        stats.meshLoadedBytes += mesh.memoryBytes();
    }
}

int run(const CliOptions& options) {
    if (options.help) {
        printHelp();
        return 0;
    }
    if (options.version) {
        std::cout << "ray " << RAY_VERSION << "\n";
        return 0;
    }
    if (options.listDevices) {
        printDeviceList(std::cout);
        return 0;
    }
    installInterruptHandlers();
    const std::filesystem::path output = checkOutputs(options);

    const std::jthread deviceStart = startDeviceEarly(options.device);  // overlaps the load
    auto loadStart = Clock::now();
    Scene scene = loadSceneFor(options);
    double loadSeconds = secondsSince(loadStart);

    checkImageFitsInMemory(options);
    ProgressBar progress(!options.quiet);
    RenderJob job{scene, options.settings, options.device, {}};
    job.progress = [&](double f) { progress.update(f); };
    job.cancel = interruptFlag();
    job.referenceBruteForce = options.referenceBruteForce;
    job.tileSize = options.tileSize;
    job.eightBit = !isFloatFormat(output);
    beginRendering();
    RenderedFrame result = render(job);
    progress.finish();
    result.stats.loadSeconds = loadSeconds;
    recordMemory(scene, result.stats);
    return finishRender(result, output, options);
}

// `ray <name> ...` runs a subcommand with a CLI11 parser of its own (in its own file);
// any other first argument is the render command's course form. A subcommand registers a
// line here. Its exceptions get the exit codes of describeFailure().
struct Subcommand {
    std::string name;
    int (*run)(const std::vector<std::string>& args);  // the arguments after the name
    const char* synopsis;  // for ray --help: its arguments, then what it does
};
const std::vector<Subcommand> kSubcommands = {
    {"view", runViewModule,  // host/viewer/, in libray_viewer.so
     "<scene.xml> [options]\n"
     "      a live viewer in the browser: orbit, zoom, switch features, click a pixel to\n"
     "      explain it; saving the scene reloads it (ray view --help)"},
    {"explain", runExplainCommand,  // host/explain/
     "<scene.xml> <x> <y> [<width> <height>] [<depth>] [options]\n"
     "      the tree of rays of pixel (x, y): every hit, light term and branch, as the\n"
     "      reference renderer traces it (ray explain --help)"},
    {"convert", runConvertCommand,  // host/app/convert_command.h
     "<in> <out> [options]\n"
     "      a scene from CS123 XML into the course's JSON or back, the format by <out>'s\n"
     "      extension (.json, .xml) (ray convert --help)"},
};

void printHelp() {
    std::cout << kUsageText << "\nsubcommands:\n";
    for (const Subcommand& subcommand : kSubcommands)
        std::cout << "  ray " << subcommand.name << " " << subcommand.synopsis << "\n";
}

// `ray vie chess.xml`: a first argument that is no file but nearly a subcommand's name is
// taken for a misspelled subcommand rather than a scene.
void refuseMisspelledSubcommand(const std::string& first) {
    std::error_code unreadable;  // a name too long for the system is no subcommand either
    if (first.empty() || first[0] == '-' || std::filesystem::exists(first, unreadable) || unreadable) return;
    std::vector<std::string> names;
    for (const Subcommand& subcommand : kSubcommands) names.push_back(subcommand.name);
    const std::string guess = closestMatch(first, names);
    if (!guess.empty())
        throw UsageError("unknown subcommand '" + first + "' (and no such scene file); did you mean 'ray " + guess +
                         "'?");
}

int dispatch(const std::vector<std::string>& args) {
    for (const Subcommand& subcommand : kSubcommands)
        if (!args.empty() && args.front() == subcommand.name)
            return subcommand.run(std::vector<std::string>(args.begin() + 1, args.end()));
    if (!args.empty()) refuseMisspelledSubcommand(args.front());
    return run(parseCommandLine(args));
}

}  // namespace

int main(int argc, char** argv) {
    restartWithHugePageHeap(argv);  // core/huge_pages.h: at most once, before any thread
    returnLargeBlocksWhenFreed();
    const std::vector<std::string> args(argv + 1, argv + argc);
#ifdef RAY_HAVE_MPI
    // Started by mpirun: the render command across every rank (distributed/mpi_render.h),
    // in libray_mpi.so.
    if (launchedByMpirun()) return endProcessCleanly(runMpiModule(argc, argv));
#endif
    int exitCode;
    try {
        exitCode = dispatch(args);
    } catch (...) {
        exitCode = reportFailure(std::current_exception());
    }
    return endProcessCleanly(exitCode);
}
