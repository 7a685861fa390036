#include "app/cli.h"

#include "app/course_config.h"
#include "devices/renderer.h"
#include "render/settings_table.h"
#include "scene/parameter_rules.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <functional>
#include <sstream>

namespace ray {

namespace {

// The render command's own options; the render settings' follow from the table.
const char* const kRenderOptionsHelp = R"(  -o, --output FILE        output image; the format follows the extension
                           (png, jpg, tif, ppm: 8-bit; exr, hdr: float, unclamped)
  --device D               auto (default: a GPU, else a CPU OpenCL device) | cpu | gpu |
                           all | ref (the host reference renderer) | an index from
                           --list-devices | a list of indices (0,2); several devices
                           (all, a list) cooperate on the frame, tile by tile
  --tile-size N            side of the square OpenCL tiles (8..4096; default automatic)
  --list-devices           list the OpenCL platforms and devices, then exit
  --no-bvh                 with --device ref: test every primitive for every ray instead
                           of searching the reference renderer's BVH (slow: the plainest
                           oracle, for checking that BVH and for timing against it)
  --strict                 treat every warning as an error
  --quiet                  no progress and no warnings
  --stats                  print rays traced, Mrays/s and timings on stderr
  --stats-json FILE        write the same statistics as JSON (with every render setting)
  --replace-read-only      replace an output file that is read-only (refused without it);
                           outputs are written through symbolic links, into devices and
                           FIFOs, and never over the scene (docs/user-guide.md)
  --max-primitives N       refuse scenes that flatten to more than N primitive
                           instances (default 50000000; memory is checked as well)
  --partial                on Ctrl-C (SIGINT) or SIGTERM, write the part rendered so far
                           (unrendered pixels black) instead of nothing
  -h, --help               this text
  --version                the version
)";

const char* const kRenderExitHelp = R"(
exit status: 0 success, 2 bad input or arguments, 3 device or runtime failure,
             130 interrupted by SIGINT, 143 by SIGTERM (the output file is left as it was,
             unless --partial)

across processes and machines (a build with MPI): mpirun [-q] -n N [--hostfile F] ray
<scene.xml> ... renders one frame on N ranks, each on its own --device; rank 0 hands out
the tiles, renders too and alone writes the image and the statistics (see docs/user-guide.md).
  --rank-timeout S         under mpirun: a rank that holds a tile S seconds, or sends
                           nothing for S seconds (a rank that answers sends a heartbeat each
                           second, also while it compiles), is taken for hung (default: from
                           the tile times seen, at least 10 s; a first tile 120 s); its
                           tiles go to the others. Exit 4: the image was written whole, but
                           a rank stopped answering and the job was ended without it
)";

std::string defaultText(const char* name) {
    const SettingSpec* spec = findSetting(name);
    const SettingValue value = settingValue(RenderSettings{}, *spec);
    return std::to_string(std::get<int64_t>(value));
}

std::string composeUsage() {
    return "usage: ray <scene.xml> [<width> <height>] [<depth>] [options]\n"
           "       ray <scene.json> [<width> <height>] [<depth>] [options]\n"
           "       ray <config.ini> [<width> <height>] [<depth>] [options]\n\n"
           "Renders a CS123 scenefile (XML) or a CS1230 one (JSON); a course config (.ini) names the scene, the\n"
           "output and the settings, and what follows it overrides them. Defaults: " +
           defaultText("width") + " " + defaultText("height") + ", depth " + defaultText("depth") +
           ", output <scene name>.png here.\n\noptions:\n" + kRenderOptionsHelp + renderSettingsHelp() +
           kRenderExitHelp;
}

}  // namespace

const std::string kUsageText = composeUsage();

int64_t parseWhole(const std::string& text, const std::string& what, int64_t lo, int64_t hi) {
    int64_t value = 0;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec == std::errc() && end == text.data() + text.size()) {
        if (value >= lo && value <= hi) return value;
    } else if (ec != std::errc::result_out_of_range || text.find_first_not_of("+-0123456789") != std::string::npos) {
        throw UsageError(what + " must be a whole number, not '" + text + "'");
    }
    throw UsageError(what + " must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", not " + text);
}

int parseInt(const std::string& text, const std::string& what, int lo, int hi) {
    return int(parseWhole(text, what, lo, hi));
}

namespace {

double parseDouble(const std::string& text, const std::string& what) {
    try {
        size_t used = 0;
        double value = std::stod(text, &used);
        if (used == text.size() && std::isfinite(value)) return value;
    } catch (const std::exception&) {
    }
    throw UsageError(what + " must be a number, not '" + text + "'");
}

}  // namespace

double parseDoubleBetween(const std::string& text, const std::string& what, double lo, double hi) {
    const double value = parseDouble(text, what);
    if (!(value >= lo && value <= hi))
        throw UsageError(what + " must be between " + formatNumber(lo) + " and " + formatNumber(hi) + ", not " + text);
    return value;
}

namespace {

void validateDevice(const std::string& text) {
    if (!isDeviceSelection(text))
        throw UsageError("--device must be auto, cpu, gpu, all, ref, a device index or a list such as 0,2, not '" +
                         text + "'");
}

// A positional ([<width> <height>] [<depth>]) into its setting, in the table's range.
void applyPositional(const std::string& text, const char* name, RenderSettings& s) {
    const SettingSpec& spec = *findSetting(name);
    setSetting(s, spec, parseWhole(text, name, int64_t(spec.minimum), int64_t(spec.maximum)), name);
}

// "a lone number after the scene is the depth": said whenever that number is refused, since
// a width alone (ray scene.xml 640) is the usual slip.
void applyLoneDepth(const std::string& value, RenderSettings& s) {
    try {
        applyPositional(value, "depth", s);
    } catch (const UsageError& e) {
        throw UsageError(std::string(e.what()) +
                         " (a lone number after the scene is the recursion depth, as in the course's "
                         "ray <scene.xml> [<width> <height>] [<depth>]; for the image's size give both "
                         "width and height, e.g. 640 480)");
    }
}

void applyPositionals(const std::vector<std::string>& positionals, CliOptions& options) {
    if (positionals.empty()) throw UsageError("no scene file given");
    if (isCourseConfig(positionals[0]))
        options.config = positionals[0];  // the scene is the config's (startFromConfig)
    else
        options.scene = positionals[0];
    applySizeAndDepth(std::vector<std::string>(positionals.begin() + 1, positionals.end()), options.settings);
}

}  // namespace

void applySizeAndDepth(const std::vector<std::string>& values, RenderSettings& s) {
    switch (values.size()) {
        case 0:
            break;
        case 1:  // ray scene.xml <depth>
            applyLoneDepth(values[0], s);
            break;
        case 3:
            applyPositional(values[2], "depth", s);
            [[fallthrough]];
        case 2:
            applyPositional(values[0], "width", s);
            applyPositional(values[1], "height", s);
            break;
        default:
            throw UsageError("too many arguments: '" + values[3] + "' (after the scene: [<width> <height>] [<depth>])");
    }
}

void addValueOption(CLI::App& app, const std::string& names, std::function<void(const std::string&)> apply) {
    app.add_option_function<std::string>(names, std::move(apply))->take_last();
}

void addSwitch(CLI::App& app, const std::string& names, std::function<void()> apply) {
    app.add_flag_callback(names, std::move(apply));
}

namespace {

// One table entry's text into its value, with ray's messages ("--aa must be off, course,
// stratified or adaptive, not 'x'"; "--samples must be between 1 and 4096, not 0").
SettingValue parseSettingValue(const SettingSpec& spec, const std::string& text) {
    const std::string option = spec.optionName();
    switch (spec.kind()) {
        case SettingKind::Integer:
            return parseWhole(text, option, int64_t(spec.minimum), int64_t(spec.maximum));
        case SettingKind::Number:
            return parseDoubleBetween(text, option, spec.minimum, spec.maximum);
        case SettingKind::Choice:
            if (!spec.choiceNamed(text))
                throw UsageError(option + " must be " + choiceNames(spec, ", ", " or ") + ", not '" + text + "'");
            return text;
        case SettingKind::Switch:
            break;
    }
    throw UsageError(option + " is a switch: it takes no value");
}

void addSettingOption(CLI::App& app, const SettingSpec& spec, RenderSettings& s) {
    const std::string option = spec.optionName();
    if (spec.kind() == SettingKind::Switch) {
        // The switch names the change from the default: --no-shadows, --fresnel.
        const bool switchedTo = !std::get<bool>(settingValue(RenderSettings{}, spec));
        addSwitch(app, option, [&s, &spec, switchedTo] { setSetting(s, spec, switchedTo, spec.optionName()); });
        return;
    }
    addValueOption(app, option,
                   [&s, &spec](const std::string& v) { setSetting(s, spec, parseSettingValue(spec, v), spec.optionName()); });
}

// What --help says of a setting after its name: the table's help with its default, range
// or choices.
std::string settingDescription(const SettingSpec& spec) {
    const SettingValue fallback = settingValue(RenderSettings{}, spec);
    std::string text(spec.help);
    switch (spec.kind()) {
        case SettingKind::Integer:
        case SettingKind::Number: {
            const double value = std::holds_alternative<int64_t>(fallback) ? double(std::get<int64_t>(fallback))
                                                                          : std::get<double>(fallback);
            return text + " (" + formatNumber(spec.minimum) + ".." + formatNumber(spec.maximum) +
                   "; default " + formatNumber(value) + ")";
        }
        case SettingKind::Switch:
            return std::get<bool>(fallback) ? text : text + " (off by default)";
        case SettingKind::Choice: {
            text += ":";
            for (size_t i = 0; i < spec.choices.size(); ++i) {
                const SettingChoice& choice = spec.choices[i];
                const bool isDefault = std::get<std::string>(fallback) == choice.name;
                std::string note = isDefault ? "default" : "";
                if (!choice.note.empty()) note += (isDefault ? "; " : "") + std::string(choice.note);
                text += std::string(i > 0 ? " |" : "") + " " + std::string(choice.name) + (note.empty() ? "" : " (" + note + ")");
            }
            return text;
        }
    }
    return text;
}

constexpr size_t kHelpNameColumn = 2, kHelpTextColumn = 27, kHelpWidth = 92;

// "  --aa MODE                antialiasing: ...", the text wrapped under its column.
std::string helpEntry(const std::string& names, const std::string& text) {
    std::string out;
    std::string line = std::string(kHelpNameColumn, ' ') + names;
    if (line.size() + 1 > kHelpTextColumn) {  // a long name: the text starts on the next line
        out = line + "\n";
        line.clear();
    }
    line.resize(kHelpTextColumn, ' ');
    bool lineEmpty = true;
    std::istringstream words(text);
    for (std::string word; words >> word;) {
        if (!lineEmpty && line.size() + 1 + word.size() > kHelpWidth) {
            out += line + "\n";
            line = std::string(kHelpTextColumn, ' ');
            lineEmpty = true;
        }
        line += (lineEmpty ? "" : " ") + word;
        lineEmpty = false;
    }
    return out + line + "\n";
}

}  // namespace

void addRenderSettingOptions(CLI::App& app, RenderSettings& s, std::vector<std::filesystem::path>& searchPaths) {
    for (const SettingSpec& spec : renderSettingsTable())
        if (!spec.positional) addSettingOption(app, spec, s);
    app.add_option_function<std::vector<std::string>>("--search-path", [&](const std::vector<std::string>& dirs) {
        for (const std::string& dir : dirs) searchPaths.emplace_back(dir);
    })->expected(1)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

std::string renderSettingsHelp() {
    std::string help = "\nrender settings (ray, ray explain and ray view take the same):\n";
    for (const SettingSpec& spec : renderSettingsTable()) {
        if (spec.positional) continue;
        const std::string names = spec.optionName() + (spec.valueName.empty() ? "" : " " + std::string(spec.valueName));
        help += helpEntry(names, settingDescription(spec));
    }
    return help + helpEntry("--search-path DIR", "also look for textures and meshes under DIR (repeatable; "
                                                 "RAY_SEARCH_PATH=dir1:dir2 does the same)");
}

namespace {

// The option table of the render command. Each option is one line: its names, and what its
// value does to the options (the converters above keep ray's messages). The render
// settings come from the table (render/settings_table.h); an option of the render command
// alone is a line here and its entry in kRenderOptionsHelp. CLI11 does the matching: names, values,
// repeats, unknown options.
void addOptions(CLI::App& app, CliOptions& options) {
    auto set = [](bool& target) { return [&target] { target = true; }; };
    addSwitch(app, "-h,--help", set(options.help));
    addSwitch(app, "--version", set(options.version));
    addValueOption(app, "-o,--output", [&](const std::string& v) { options.output = v; });
    addRenderSettingOptions(app, options.settings, options.searchPaths);
    addValueOption(app, "--device", [&](const std::string& v) { validateDevice(v); options.device = v; });
    addSwitch(app, "--list-devices", set(options.listDevices));
    addValueOption(app, "--tile-size", [&](const std::string& v) { options.tileSize = parseInt(v, "--tile-size", 8, 4096); });
    addValueOption(app, "--rank-timeout", [&](const std::string& v) {
        options.rankTimeout = parseDoubleBetween(v, "--rank-timeout", 0.1, 1e6);
    });
    addSwitch(app, "--no-bvh", set(options.referenceBruteForce));
    addSwitch(app, "--strict", set(options.strict));
    addSwitch(app, "-q,--quiet", set(options.quiet));
    addSwitch(app, "--stats", set(options.stats));
    addValueOption(app, "--stats-json", [&](const std::string& v) { options.statsJson = v; });
    addSwitch(app, "--replace-read-only", set(options.replaceReadOnly));
    addSwitch(app, "--partial", set(options.partial));
    addValueOption(app, "--max-primitives", [&](const std::string& v) {
        options.maxPrimitives = size_t(parseInt(v, "--max-primitives", 1, 2147483647));
    });
}

// Levenshtein distance, for "did you mean".
size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

std::string withoutDashes(const std::string& name) { return name.substr(std::min(name.find_first_not_of('-'), name.size())); }

// Every name of the app's options ("-o", "--output", ...).
std::vector<std::string> optionNames(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::Option* option : app.get_options()) {
        for (const std::string& name : option->get_snames()) names.push_back("-" + name);
        for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
    }
    return names;
}

// The option a CLI11 message is about: the first of the app's names it mentions.
std::string optionNamed(const std::string& message, const CLI::App& app) {
    std::string best;
    for (const std::string& name : optionNames(app))
        if (name.size() > best.size() && message.find(name) != std::string::npos) best = name;
    return best;
}

bool isSwitch(const std::string& name, const CLI::App& app) {
    const CLI::Option* option = app.get_option_no_throw(name);
    return option && option->get_expected_max() == 0;
}

// CLI11's own errors in ray's words (the tests and scripts match on these).
UsageError usageErrorFrom(const CLI::ParseError& error, const CLI::App& app) {
    const std::string message = error.what();
    if (dynamic_cast<const CLI::ExtrasError*>(&error)) {
        const std::vector<std::string> extras = app.remaining();
        const std::string first = extras.empty() ? std::string() : extras.front();
        if (first.empty() || first[0] != '-' || first == "-")
            return UsageError("too many arguments: '" + first + "'");
        const std::string name = first.substr(0, first.find('='));
        const std::string guess = closestMatch(name, optionNames(app));
        return UsageError("unknown option '" + name + "'" + (guess.empty() ? "" : "; did you mean " + guess + "?"));
    }
    const std::string option = optionNamed(message, app);
    if (!option.empty() && isSwitch(option, app)) return UsageError(option + " is a switch: it takes no value");
    if (!option.empty() && dynamic_cast<const CLI::ArgumentMismatch*>(&error))
        return UsageError(option + " needs a value");
    if (!option.empty()) return UsageError(option + " was not understood");
    return UsageError("the arguments were not understood");
}

}  // namespace

std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates) {
    // A name the word is part of (--shadow: --no-shadows) beats one a few letters away.
    const std::string bare = withoutDashes(word);
    if (bare.size() >= 3)
        for (const std::string& candidate : candidates)
            if (withoutDashes(candidate).find(bare) != std::string::npos) return candidate;
    std::string best;
    size_t bestDistance = std::max<size_t>(2, bare.size() / 3) + 1;
    for (const std::string& candidate : candidates) {
        const size_t distance = editDistance(bare, withoutDashes(candidate));
        if (distance < bestDistance) {
            best = candidate;
            bestDistance = distance;
        }
    }
    return best;
}

void parseArguments(CLI::App& app, const std::vector<std::string>& args) {
    // CLI11 lets a switch take a value (--strict=yes, --strict=0); ray's switches take none.
    for (const std::string& arg : args) {
        if (arg == "--") break;
        const size_t equals = arg.find('=');
        if (arg.rfind("--", 0) == 0 && equals != std::string::npos && isSwitch(arg.substr(0, equals), app))
            throw UsageError(arg.substr(0, equals) + " is a switch: it takes no value");
    }
    // CLI11 takes a vector in reverse order (it pops arguments off the back).
    std::vector<std::string> reversed(args.rbegin(), args.rend());
    try {
        app.parse(reversed);
    } catch (const CLI::ParseError& e) {
        throw usageErrorFrom(e, app);
    }
}

void defineRenderCommand(CLI::App& app, CliOptions& options, std::vector<std::string>& positionals) {
    app.set_help_flag();  // ray prints its own kUsageText for -h/--help
    addOptions(app, options);
    app.add_option("positionals", positionals);  // <scene.xml> [<width> <height>] [<depth>]
}

namespace {

// The command line read once into scratch options: its positionals and --strict are known
// before the options apply, so that a config can go under them.
CliOptions readOnce(const std::vector<std::string>& args, std::vector<std::string>& positionals) {
    CliOptions scratch;
    CLI::App app("ray", "ray");
    defineRenderCommand(app, scratch, positionals);
    parseArguments(app, args);
    return scratch;
}

// `ray CONFIG.ini ...`: the config's scene, output and settings, for the options to override.
void startFromConfig(const std::filesystem::path& file, bool strict, CliOptions& options) {
    CourseConfig config = loadCourseConfig(file, options.settings, strict);
    options.config = file;
    options.scene = config.scene;
    options.output = config.output;
    options.configOutput = config.output;
    options.settings = config.settings;
    options.configWarnings = std::move(config.warnings);
}

}  // namespace

CliOptions parseCommandLine(const std::vector<std::string>& args) {
    CliOptions options;
    std::vector<std::string> positionals;
    {
        const CliOptions first = readOnce(args, positionals);
        if (!positionals.empty() && isCourseConfig(positionals[0]) && !first.help && !first.version &&
            !first.listDevices)
            startFromConfig(positionals[0], first.strict, options);
        positionals.clear();
    }
    CLI::App app("ray", "ray");
    defineRenderCommand(app, options, positionals);
    parseArguments(app, args);
    if (options.help || options.version || options.listDevices) {
        if (!positionals.empty()) applyPositionals(positionals, options);
        return options;
    }
    applyPositionals(positionals, options);
    const RenderSettings& s = options.settings;
    const bool samplesGiven = app.get_option("--samples")->count() > 0;
    if (samplesGiven && (s.antialias == AntialiasMode::Off || s.antialias == AntialiasMode::Course))
        throw UsageError("--samples applies to --aa stratified or adaptive; add one of those");
    if (options.referenceBruteForce && options.device != "ref" && options.device != "reference")
        throw UsageError("--no-bvh applies to the reference renderer (the OpenCL kernel always uses its BVH); add --device ref");
    return options;
}

std::filesystem::path outputPathFor(const CliOptions& options) {
    if (!options.output.empty()) return options.output;
    return std::filesystem::path(options.scene.stem().string() + ".png");
}

}  // namespace ray
