// ray: renders a CS123 scenefile. See `ray --help` and README.md.
#include <atomic>
#include <chrono>
#include <csignal>
#include <signal.h>
#include <unistd.h>
#include <iostream>
#include <string_view>
#include <vector>

#include "app/cli.h"
#include "core/atomic_file.h"
#include "explain/explain_command.h"
#include "viewer/view_command.h"
#include "scene/file_search.h"
#include "image/image.h"
#include "core/memory_limits.h"
#include "app/progress.h"
#include "reference/reference_renderer.h"
#include "render/render_stats.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"

namespace {

using namespace ray;
using Clock = std::chrono::steady_clock;

constexpr int kExitBadInput = 2;
constexpr int kExitRuntime = 3;

// Ctrl-C (SIGINT) and SIGTERM: ray exits with 128 + the signal's number, the shell's
// convention (130 for Ctrl-C). Before the render nothing has been written, so the handler
// exits at once; during it, the handler only sets gInterrupted (a lock-free atomic is
// async-signal-safe), the renderers poll it and stop within about a second, and run()
// writes the partial image or nothing. A signal while the finished image is being written
// lets the write complete. SA_RESETHAND restores the default action, so a second Ctrl-C
// kills at once.
std::atomic<bool> gInterrupted{false};
std::atomic<bool> gRendering{false};
volatile std::sig_atomic_t gSignal = 0;

extern "C" void onInterruptSignal(int signal) {
    gSignal = signal;
    if (!gRendering.load()) _exit(128 + signal);
    gInterrupted.store(true);
}

void installInterruptHandlers() {
    struct sigaction action {};
    action.sa_handler = onInterruptSignal;
    action.sa_flags = SA_RESETHAND;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Catches problems with the output path before any rendering time is spent.
void checkOutputPath(const std::filesystem::path& output) {
    if (!canWriteImageFormat(output))
        throw UsageError("cannot write an image in the format of '" + output.string() + "' (its extension names none " +
                         "this build of OpenImageIO can write); " + kOutputFormatAdvice);
    std::filesystem::path folder = output.parent_path();
    if (!folder.empty() && !std::filesystem::is_directory(folder))
        throw UsageError("the output folder '" + folder.string() + "' does not exist");
    checkCanWriteBeside(output);  // an unwritable folder: exit 3 now, not after the render
}

// Refuses, before the BVH is built, an image this machine has not the memory for (the
// CLI caps each side at kMaxImageSide, but 16384² floats alone need 3 GiB).
void checkImageFitsInMemory(const CliOptions& options) {
    const RenderSettings& s = options.settings;
    const bool reference = isReferenceDevice(options.device);
    const uint64_t perPixel = reference ? kHostBytesPerPixelReference : kHostBytesPerPixelOpenCl;
    if (auto shortfall = hostMemoryShortfall(uint64_t(s.width) * uint64_t(s.height) * perPixel))
        throw UsageError("a " + std::to_string(s.width) + "x" + std::to_string(s.height) + " image " + *shortfall +
                         "; render a smaller image (the width and height arguments)");
}

// After SIGINT/SIGTERM: the output file is left as it was, or with --partial gets what was
// rendered (unrendered pixels black).
int finishInterrupted(const RenderOutput& result, const std::filesystem::path& output, const CliOptions& options) {
    const int signal = gSignal ? int(gSignal) : SIGINT;
    if (options.partial) {
        writeImage(result.image, output);
        std::cerr << "ray: interrupted; wrote the partial image to " << output.string() << "\n";
    } else {
        std::cerr << "ray: interrupted; " << output.string()
                  << " was not written (--partial writes what was rendered)\n";
    }
    return 128 + signal;
}

int run(const CliOptions& options) {
    if (options.help) {
        std::cout << kUsageText;
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
    const std::filesystem::path output = outputPathFor(options);
    checkOutputPath(output);
    if (!options.statsJson.empty()) checkCanWriteBeside(options.statsJson);

    auto loadStart = Clock::now();
    LoadOptions load;
    load.searchPaths = options.searchPaths;
    for (auto& p : searchPathsFromEnvironment()) load.searchPaths.push_back(p);
    load.strict = options.strict;
    load.maxPrimitives = options.maxPrimitives;
    load.loadImages = options.settings.textures;
    load.warn = [&](const std::string& message) {
        if (!options.quiet) std::cerr << message << "\n";
    };
    Scene scene = loadScene(options.scene, load);
    double loadSeconds = secondsSince(loadStart);

    checkImageFitsInMemory(options);
    ProgressBar progress(!options.quiet);
    RenderJob job{scene, options.settings, options.device, {}};
    job.progress = [&](double f) { progress.update(f); };
    job.cancel = &gInterrupted;
    job.referenceBruteForce = options.referenceBruteForce;
    job.tileSize = options.tileSize;
    gRendering = true;
    RenderOutput result = render(job);
    progress.finish();
    for (const std::string& warning : result.stats.warnings) std::cerr << "ray: warning: " << warning << "\n";
    result.stats.loadSeconds = loadSeconds;
    if (result.interrupted) return finishInterrupted(result, output, options);

    writeImage(result.image, output);
    if (!options.quiet) std::cerr << "wrote " << output.string() << "\n";
    if (options.stats) printStats(result.stats, std::cerr);
    if (!options.statsJson.empty()) writeStatsJson(result.stats, options.statsJson);
    return 0;
}

// `ray <name> ...` runs a subcommand with a CLI11 parser of its own (in its own file);
// any other first argument is the render command's course form. A subcommand registers a
// line here. Its exceptions get the exit codes below.
struct Subcommand {
    std::string_view name;
    int (*run)(const std::vector<std::string>& args);  // the arguments after the name
};
const std::vector<Subcommand> kSubcommands = {
    {"explain", runExplainCommand},  // host/explain/
    {"view", runViewCommand},        // host/viewer/
};

int dispatch(const std::vector<std::string>& args) {
    for (const Subcommand& subcommand : kSubcommands)
        if (!args.empty() && args.front() == subcommand.name)
            return subcommand.run(std::vector<std::string>(args.begin() + 1, args.end()));
    return run(parseCommandLine(args));
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return dispatch(std::vector<std::string>(argv + 1, argv + argc));
    } catch (const UsageError& e) {
        std::cerr << "ray: " << e.what() << "\n(see ray --help)\n";
        return kExitBadInput;
    } catch (const InputError& e) {
        std::cerr << e.what() << "\n";
        return kExitBadInput;
    } catch (const DeviceError& e) {
        std::cerr << "ray: " << e.what() << "\n";
        return kExitRuntime;
    } catch (const ImageError& e) {
        std::cerr << "ray: " << e.what() << "\n";
        return kExitRuntime;
    } catch (const std::bad_alloc&) {
        std::cerr << "ray: out of memory; try a smaller image, fewer samples or a smaller scene\n";
        return kExitRuntime;
    } catch (const std::exception& e) {
        std::cerr << "ray: " << e.what() << "\n";
        return kExitRuntime;
    }
}
