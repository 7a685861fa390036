// The render command's steps (`ray <scene.xml> [w h] [depth] [options]`), shared by the
// one-process run (main.cpp) and the distributed one under mpirun (distributed/).
#pragma once

#include <atomic>
#include <exception>
#include <filesystem>
#include <string>

#include "app/cli.h"
#include "devices/renderer.h"
#include "scene/scene.h"

namespace ray {

constexpr int kExitBadInput = 2;  // the command line, the scene or its files
constexpr int kExitRuntime = 3;   // a device, memory, or an output that cannot be written

// What an exception means to the user: the exit code and the message, as printed.
struct Failure {
    int exitCode = 0;
    std::string message;  // several lines at most, without the final newline
};
Failure describeFailure(std::exception_ptr error);
// Prints describeFailure's message to stderr; returns its exit code.
int reportFailure(std::exception_ptr error);

// Ctrl-C (SIGINT) and SIGTERM: ray exits with 128 + the signal's number, the shell's
// convention (130 for Ctrl-C). Before beginRendering() nothing has been written, so the
// handler exits at once; after it, the handler only sets the flag interruptFlag() gives
// (a lock-free atomic is async-signal-safe), the renderers poll it and stop within about
// a second, and the command writes the partial image or nothing. SA_RESETHAND restores the
// default action, so a second Ctrl-C kills at once.
void installInterruptHandlers();
void beginRendering();
const std::atomic<bool>* interruptFlag();
int interruptExitCode();  // 128 + the signal received

// Checks the output image's path (and --stats-json's) before any rendering time is spent
// and returns it. Throws UsageError, FileWriteError.
std::filesystem::path checkOutputs(const CliOptions& options);
// Loads the scene with the command line's search paths and limits; warnings go to stderr
// unless --quiet. Throws InputError.
Scene loadSceneFor(const CliOptions& options);
// Refuses, before the BVH is built, an image this machine has not the memory for.
void checkImageFitsInMemory(const CliOptions& options);

// After the render: prints the devices' warnings, writes the image (or after an interrupt
// the partial image with --partial, else nothing), the statistics; returns the exit code.
int finishRender(const RenderedFrame& result, const std::filesystem::path& output, const CliOptions& options);

}  // namespace ray
