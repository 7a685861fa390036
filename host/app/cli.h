// The command line: `ray <scene.xml> [<width> <height>] [<depth>] [options]` (SPEC §6).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "render/render_settings.h"

namespace ray {

struct CliOptions {
    std::filesystem::path scene;
    std::filesystem::path output;  // empty: <scene name>.png in the current folder
    RenderSettings settings;
    std::string device = "auto";  // auto | cpu | gpu | all | ref | <index> | <index>,<index>...
    int tileSize = 0;             // --tile-size; 0: automatic
    double rankTimeout = 0;       // --rank-timeout (mpirun): seconds; 0: from the tile times
    std::vector<std::filesystem::path> searchPaths;
    bool strict = false;
    bool quiet = false;
    bool stats = false;
    std::filesystem::path statsJson;
    // On SIGINT/SIGTERM, write what was rendered so far instead of nothing (--partial).
    bool partial = false;
    // Refuse scenes that flatten to more primitive instances (--max-primitives).
    size_t maxPrimitives = 50'000'000;
    bool listDevices = false;
    // --device ref tests every primitive for every ray instead of using its BVH (--no-bvh).
    bool referenceBruteForce = false;
    bool help = false;
    bool version = false;
};

// Thrown for bad arguments; the message says what is wrong and what to do.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Parses argv (argv[0] excluded). Throws UsageError.
CliOptions parseCommandLine(const std::vector<std::string>& args);

// The output file for the options: --output, or the scene's name with .png here.
std::filesystem::path outputPathFor(const CliOptions& options);

extern const char* const kUsageText;

}  // namespace ray
