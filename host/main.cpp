// ray: renders a CS123 scenefile. See `ray --help` and README.md.
#include <atomic>
#include <chrono>
#include <csignal>
#include <iostream>

#include "cli.h"
#include "file_search.h"
#include "image.h"
#include "progress.h"
#include "reference_renderer.h"
#include "render_stats.h"
#include "renderer.h"
#include "scene_loader.h"

namespace {

using namespace ray;
using Clock = std::chrono::steady_clock;

constexpr int kExitBadInput = 2;
constexpr int kExitRuntime = 3;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Catches problems with the output path before any rendering time is spent.
void checkOutputPath(const std::filesystem::path& output) {
    static const char* const kKnown[] = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".ppm", ".pnm",
                                         ".bmp", ".tga", ".exr", ".hdr", ".pfm"};
    std::string ext = output.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    bool known = false;
    for (const char* k : kKnown) known = known || ext == k;
    if (!known)
        throw UsageError("cannot tell the image format of '" + output.string() +
                         "' from its extension; use .png, .jpg, .tif, .ppm, .exr, .hdr or .pfm");
    std::filesystem::path folder = output.parent_path();
    if (!folder.empty() && !std::filesystem::is_directory(folder))
        throw UsageError("the output folder '" + folder.string() + "' does not exist");
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
    const std::filesystem::path output = outputPathFor(options);
    checkOutputPath(output);

    auto loadStart = Clock::now();
    LoadOptions load;
    load.searchPaths = options.searchPaths;
    for (auto& p : searchPathsFromEnvironment()) load.searchPaths.push_back(p);
    load.strict = options.strict;
    load.loadImages = options.settings.textures;
    load.warn = [&](const std::string& message) {
        if (!options.quiet) std::cerr << message << "\n";
    };
    Scene scene = loadScene(options.scene, load);
    double loadSeconds = secondsSince(loadStart);

    ProgressBar progress(!options.quiet);
    RenderJob job{scene, options.settings, options.device, {}};
    job.progress = [&](double f) { progress.update(f); };
    RenderOutput result = render(job);
    progress.finish();
    result.stats.loadSeconds = loadSeconds;

    writeImage(result.image, output);
    if (!options.quiet) std::cerr << "wrote " << output.string() << "\n";
    if (options.stats) printStats(result.stats, std::cerr);
    if (!options.statsJson.empty()) writeStatsJson(result.stats, options.statsJson);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        CliOptions options = parseCommandLine(std::vector<std::string>(argv + 1, argv + argc));
        return run(options);
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
