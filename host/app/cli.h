// The command line: `ray <scene.xml> [<width> <height>] [<depth>] [options]` (SPEC §6), and
// `ray CONFIG.ini [<width> <height>] [<depth>] [options]`: a course config (SPEC §7), which
// the options and positionals after it override.
#pragma once

#include <filesystem>
#include <cstdint>
#include <optional>
#include <functional>
#include <string>
#include <vector>

#include "core/usage_error.h"
#include "render/render_settings.h"

namespace CLI {
class App;
}

namespace ray {

struct CliOptions {
    std::filesystem::path scene;
    // `ray CONFIG.ini`: the course's config (app/course_config.h) the scene, the output and the
    // settings came from before the options overrode them; empty for `ray scene.xml`.
    std::filesystem::path config;
    std::filesystem::path configOutput;  // the config's output, whose folder is made if missing
    std::vector<std::string> configWarnings;  // complete, printed unless --quiet
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
    // Replace an output (image, --stats-json) that is a read-only file (--replace-read-only).
    bool replaceReadOnly = false;
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

// Parses argv (argv[0] excluded). Throws UsageError.
CliOptions parseCommandLine(const std::vector<std::string>& args);

// The render command's parser, as parseCommandLine builds it: its options write to
// `options`, its positionals (<scene.xml> [<width> <height>] [<depth>]) to `positionals`.
// The manual page and the shell completion read the options' names off it
// (app/command_reference.h).
void defineRenderCommand(CLI::App& app, CliOptions& options, std::vector<std::string>& positionals);

// The output file for the options: --output, or the scene's name with .png here.
std::filesystem::path outputPathFor(const CliOptions& options);

// ray --help: the render command's options, then the render settings' (renderSettingsHelp).
extern const std::string kUsageText;

// What the subcommands share with the render command: ray's value parsers (each message
// names the option and what it takes), the render settings' options, and CLI11 with its
// errors put in ray's words. Each throws UsageError.
int parseInt(const std::string& text, const std::string& what, int lo, int hi);
int64_t parseWhole(const std::string& text, const std::string& what, int64_t lo, int64_t hi);
double parseDoubleBetween(const std::string& text, const std::string& what, double lo, double hi);

// An option with a value, parsed by `apply` (CLI11 only matches the names), and a switch.
void addValueOption(CLI::App& app, const std::string& names, std::function<void(const std::string&)> apply);
void addSwitch(CLI::App& app, const std::string& names, std::function<void()> apply);

// The options of RenderSettings that every command that traces takes, one for each entry
// of the settings table (render/settings_table.h) but the positional width, height and
// depth (--aa, --samples, ..., --no-shadows, ..., --texture-filter); and
// --search-path.
void addRenderSettingOptions(CLI::App& app, RenderSettings& settings, std::vector<std::filesystem::path>& searchPaths);

// Those options' part of --help, generated from the table: names, help, defaults, ranges
// and choices, as "\nrender settings ...:\n  --aa MODE   antialiasing: ...\n".
std::string renderSettingsHelp();

// The course's [<width> <height>] [<depth>] after the scene: a lone number is the depth.
void applySizeAndDepth(const std::vector<std::string>& values, RenderSettings& settings);

// Parses args (argv without the program and subcommand names) with `app`. CLI11's own
// errors become UsageErrors in ray's words: unknown options get a "did you mean".
void parseArguments(CLI::App& app, const std::vector<std::string>& args);

// The candidate `word` is most likely a misspelling of, or empty when none is close.
std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace ray
