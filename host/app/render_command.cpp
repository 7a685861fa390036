#include "app/render_command.h"

#include <csignal>
#include <iostream>
#include <signal.h>
#include <unistd.h>

#include "core/atomic_file.h"
#include "core/memory_limits.h"
#include "image/image.h"
#include "image/image_write.h"
#include "reference/reference_renderer.h"
#include "render/render_stats.h"
#include "scene/file_search.h"
#include "scene/scene_loader.h"

namespace ray {

namespace {

std::atomic<bool> gInterrupted{false};
std::atomic<bool> gRendering{false};
volatile std::sig_atomic_t gSignal = 0;

extern "C" void onInterruptSignal(int signal) {
    gSignal = signal;
    if (!gRendering.load()) _exit(128 + signal);
    gInterrupted.store(true);
}

}  // namespace

Failure describeFailure(std::exception_ptr error) {
    try {
        std::rethrow_exception(error);
    } catch (const UsageError& e) {
        return {kExitBadInput, std::string("ray: ") + e.what() + "\n(see ray --help)"};
    } catch (const InputError& e) {
        return {kExitBadInput, e.what()};  // "file:line: what is wrong"
    } catch (const OutputRefused& e) {  // a folder, a read-only file, the scene itself as an output
        return {kExitBadInput, std::string("ray: ") + e.what()};
    } catch (const std::bad_alloc&) {
        return {kExitRuntime, "ray: out of memory; try a smaller image, fewer samples or a smaller scene"};
    } catch (const std::exception& e) {  // DeviceError, ImageError, FileWriteError and the rest
        return {kExitRuntime, std::string("ray: ") + e.what()};
    } catch (...) {
        return {kExitRuntime, "ray: an unknown error"};
    }
}

int reportFailure(std::exception_ptr error) {
    const Failure failure = describeFailure(error);
    std::cerr << failure.message << "\n";
    return failure.exitCode;
}

void installInterruptHandlers() {
    struct sigaction action {};
    action.sa_handler = onInterruptSignal;
    action.sa_flags = SA_RESETHAND;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

void beginRendering() { gRendering = true; }

const std::atomic<bool>* interruptFlag() { return &gInterrupted; }

int interruptExitCode() { return 128 + (gSignal ? int(gSignal) : SIGINT); }

namespace {

// How the command's outputs are written (core/atomic_file.h).
WriteOptions writeOptionsFor(const CliOptions& options) {
    WriteOptions write;
    write.replaceReadOnly = options.replaceReadOnly;
    return write;
}

}  // namespace

std::filesystem::path checkOutputs(const CliOptions& options) {
    const std::filesystem::path output = outputPathFor(options);
    refuseWritingOverInput(output, options.output.empty() ? "the output image" : "-o", options.scene, "the scene");
    if (!canWriteImageFormat(output))
        throw UsageError("cannot write an image in the format of '" + output.string() + "' (its extension names none " +
                         "this build of OpenImageIO can write); " + kOutputFormatAdvice);
    std::filesystem::path folder = output.parent_path();
    if (!folder.empty() && output == options.configOutput) {  // a course config's output: its folder is made
        std::error_code ec;
        std::filesystem::create_directories(folder, ec);
    }
    if (!folder.empty() && !std::filesystem::is_directory(folder))
        throw UsageError("the output folder '" + folder.string() + "' does not exist");
    // A folder, a read-only file: exit 2 now, not after the render; an unwritable folder:
    // exit 3 now.
    checkCanWrite(output, writeOptionsFor(options));
    if (!options.statsJson.empty()) {
        refuseWritingOverInput(options.statsJson, "--stats-json", options.scene, "the scene");
        refuseWritingOverInput(options.statsJson, "--stats-json", output, "the output image");
        checkCanWrite(options.statsJson, writeOptionsFor(options));
    }
    return output;
}

Scene loadSceneFor(const CliOptions& options) {
    LoadOptions load;
    load.searchPaths = options.searchPaths;
    for (auto& p : searchPathsFromEnvironment()) load.searchPaths.push_back(p);
    load.strict = options.strict;
    load.maxPrimitives = options.maxPrimitives;
    load.loadImages = options.settings.textures;
    load.warn = [&](const std::string& message) {
        if (!options.quiet) std::cerr << message << "\n";
    };
    for (const std::string& warning : options.configWarnings) load.warn(warning);
    return loadScene(options.scene, load);
}

// The CLI caps each side at kMaxImageSide, but 16384² floats alone need 3 GiB.
void checkImageFitsInMemory(const CliOptions& options) {
    const RenderSettings& s = options.settings;
    if (auto shortfall = hostMemoryShortfall(uint64_t(s.width) * uint64_t(s.height) * kHostBytesPerPixel))
        throw UsageError("a " + std::to_string(s.width) + "x" + std::to_string(s.height) + " image " + *shortfall +
                         "; render a smaller image (the width and height arguments)");
}

namespace {

// The image of a render: 8-bit when the render kept it so (RenderJob::eightBit).
void writeRendered(const RenderedFrame& result, const std::filesystem::path& output, const CliOptions& options) {
    if (!result.bytes.empty())
        writeImage(result.bytes, output, writeOptionsFor(options));
    else
        writeImage(result.image, output, writeOptionsFor(options));
}

}  // namespace

int finishRender(const RenderedFrame& result, const std::filesystem::path& output, const CliOptions& options) {
    for (const std::string& warning : result.stats.warnings) std::cerr << "ray: warning: " << warning << "\n";
    if (result.cancelled) {
        // The output file is left as it was, or with --partial gets what was rendered
        // (unrendered pixels black).
        if (options.partial) {
            writeRendered(result, output, options);
            std::cerr << "ray: interrupted; wrote the partial image to " << output.string() << "\n";
        } else {
            std::cerr << "ray: interrupted; " << output.string()
                      << " was not written (--partial writes what was rendered)\n";
        }
        return interruptExitCode();
    }
    writeRendered(result, output, options);
    if (!options.quiet) std::cerr << "wrote " << output.string() << "\n";
    if (options.stats) printStats(result.stats, std::cerr);
    if (!options.statsJson.empty())
        writeFileAtomically(options.statsJson, statsToJson(result.stats, options.settings), writeOptionsFor(options));
    return 0;
}

}  // namespace ray
