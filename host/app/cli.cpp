#include "app/cli.h"

#include <sstream>

#include <charconv>
#include <cmath>

namespace ray {

const char* const kUsageText = R"(usage: ray <scene.xml> [<width> <height>] [<depth>] [options]

Renders a CS123 scenefile. Defaults: 1024 768, depth 4, output <scene name>.png here.

options:
  -o, --output FILE        output image; the format follows the extension
                           (png, jpg, tif, ppm: 8-bit; exr, hdr: float, unclamped)
  --aa MODE                antialiasing: off | course (default; the course's adaptive
                           4..64 samples) | stratified | adaptive
  --samples N              samples per pixel for stratified/adaptive (default 16)
  --seed N                 seed of the stochastic sampling (default 0)
  --area-samples N         point samples per area light, a jittered k×k grid with
                           k = floor(sqrt(N)) (default 16, at most 1024)
  --shutter T              motion blur: the shutter stays open over the fraction T of the
                           scene's <motion> (0..1; default 1, the whole motion; 0 renders
                           the scene at rest). Every camera sample takes its own time
  --threshold T            stop a reflected/refracted branch whose weight is below T
                           in every channel (default 1/256)
  --device D               auto (default: a GPU, else a CPU OpenCL device) | cpu | gpu |
                           all | ref (the host reference renderer) | an index from
                           --list-devices | a list of indices (0,2); several devices
                           (all, a list) cooperate on the frame, tile by tile
  --tile-size N            side of the square OpenCL tiles (8..4096; default automatic)
  --list-devices           list the OpenCL platforms and devices, then exit
  --no-bvh                 with --device ref: test every primitive for every ray instead
                           of searching the reference renderer's BVH (slow: the plainest
                           oracle, for checking that BVH and for timing against it)
  --search-path DIR        also look for textures and meshes under DIR (repeatable;
                           RAY_SEARCH_PATH=dir1:dir2 does the same)
  --strict                 treat every warning as an error
  --no-shadows, --no-reflections, --no-refraction, --no-textures, --no-dof
                           switch a feature off (the course's test settings)
  --texture-filter F       nearest (default, as the course) | bilinear | trilinear
  --quiet                  no progress and no warnings
  --stats                  print rays traced, Mrays/s and timings on stderr
  --stats-json FILE        write the same statistics as JSON
  --max-primitives N       refuse scenes that flatten to more than N primitive
                           instances (default 50000000; memory is checked as well)
  --partial                on Ctrl-C (SIGINT) or SIGTERM, write the part rendered so far
                           (unrendered pixels black) instead of nothing
  -h, --help               this text
  --version                the version

exit status: 0 success, 2 bad input or arguments, 3 device or runtime failure,
             130 interrupted by SIGINT, 143 by SIGTERM (the output file is left as it was,
             unless --partial)
)";

namespace {

int parseInt(const std::string& text, const std::string& what, int lo, int hi) {
    int value = 0;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size())
        throw UsageError(what + " must be a whole number, not '" + text + "'");
    if (value < lo || value > hi)
        throw UsageError(what + " must be between " + std::to_string(lo) + " and " + std::to_string(hi) +
                         ", not " + text);
    return value;
}

double parseDouble(const std::string& text, const std::string& what) {
    try {
        size_t used = 0;
        double value = std::stod(text, &used);
        if (used == text.size() && std::isfinite(value)) return value;
    } catch (const std::exception&) {
    }
    throw UsageError(what + " must be a number, not '" + text + "'");
}

AntialiasMode parseAntialias(const std::string& text) {
    if (text == "off") return AntialiasMode::Off;
    if (text == "course") return AntialiasMode::Course;
    if (text == "stratified") return AntialiasMode::Stratified;
    if (text == "adaptive") return AntialiasMode::Adaptive;
    throw UsageError("--aa must be off, course, stratified or adaptive, not '" + text + "'");
}

TextureFilter parseTextureFilter(const std::string& text) {
    if (text == "nearest") return TextureFilter::Nearest;
    if (text == "bilinear") return TextureFilter::Bilinear;
    if (text == "trilinear") return TextureFilter::Trilinear;
    throw UsageError("--texture-filter must be nearest, bilinear or trilinear, not '" + text + "'");
}

void validateDevice(const std::string& text) {
    if (text == "auto" || text == "cpu" || text == "gpu" || text == "all" || text == "ref" || text == "reference")
        return;
    std::stringstream list(text);
    for (std::string item; std::getline(list, item, ',');)
        parseInt(item, "--device (auto, cpu, gpu, all, ref, a device index or a list such as 0,2)", 0, 1 << 20);
    if (text.empty() || text.back() == ',') throw UsageError("--device needs a device name, index or list such as 0,2");
}

void applyPositionals(const std::vector<std::string>& positionals, CliOptions& options) {
    if (positionals.empty()) throw UsageError("no scene file given");
    options.scene = positionals[0];
    RenderSettings& s = options.settings;
    switch (positionals.size()) {
        case 1:
            break;
        case 2:  // ray scene.xml <depth>
            s.maxDepth = parseInt(positionals[1], "depth", 0, kMaxDepth);
            break;
        case 4:
            s.maxDepth = parseInt(positionals[3], "depth", 0, kMaxDepth);
            [[fallthrough]];
        case 3:
            s.width = parseInt(positionals[1], "width", 1, kMaxImageSide);
            s.height = parseInt(positionals[2], "height", 1, kMaxImageSide);
            break;
        default:
            throw UsageError("too many arguments: '" + positionals[4] + "'");
    }
}

}  // namespace

CliOptions parseCommandLine(const std::vector<std::string>& args) {
    CliOptions options;
    RenderSettings& s = options.settings;
    std::vector<std::string> positionals;
    bool samplesGiven = false;

    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& arg = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw UsageError(arg + " needs a value");
            return args[++i];
        };
        if (arg == "-h" || arg == "--help") options.help = true;
        else if (arg == "--version") options.version = true;
        else if (arg == "-o" || arg == "--output") options.output = value();
        else if (arg == "--aa") s.antialias = parseAntialias(value());
        else if (arg == "--samples") { s.samples = parseInt(value(), "--samples", 1, kMaxSamples); samplesGiven = true; }
        else if (arg == "--area-samples") s.areaSamples = parseInt(value(), "--area-samples", 1, kMaxAreaSamples);
        else if (arg == "--seed") s.seed = uint32_t(parseInt(value(), "--seed", 0, 2147483647));
        else if (arg == "--shutter") {
            s.shutter = parseDouble(value(), "--shutter");
            if (!(s.shutter >= 0 && s.shutter <= 1)) throw UsageError("--shutter must be between 0 and 1");
        }
        else if (arg == "--threshold") {
            s.weightThreshold = parseDouble(value(), "--threshold");
            if (s.weightThreshold < 0 || s.weightThreshold > 1) throw UsageError("--threshold must be between 0 and 1");
        }
        else if (arg == "--device") { options.device = value(); validateDevice(options.device); }
        else if (arg == "--list-devices") options.listDevices = true;
        else if (arg == "--tile-size") options.tileSize = parseInt(value(), "--tile-size", 8, 4096);
        else if (arg == "--no-bvh") options.referenceBruteForce = true;
        else if (arg == "--search-path") options.searchPaths.emplace_back(value());
        else if (arg == "--strict") options.strict = true;
        else if (arg == "--no-shadows") s.shadows = false;
        else if (arg == "--no-reflections") s.reflections = false;
        else if (arg == "--no-refraction") s.refraction = false;
        else if (arg == "--no-textures") s.textures = false;
        else if (arg == "--no-dof") s.depthOfField = false;
        else if (arg == "--texture-filter") s.textureFilter = parseTextureFilter(value());
        else if (arg == "--quiet" || arg == "-q") options.quiet = true;
        else if (arg == "--stats") options.stats = true;
        else if (arg == "--stats-json") options.statsJson = value();
        else if (arg == "--partial") options.partial = true;
        else if (arg == "--max-primitives") options.maxPrimitives = size_t(parseInt(value(), "--max-primitives", 1, 2147483647));
        else if (arg.size() > 1 && arg[0] == '-' && !(arg[1] >= '0' && arg[1] <= '9'))
            throw UsageError("unknown option '" + arg + "'");
        else positionals.push_back(arg);
    }
    if (options.help || options.version || options.listDevices) {
        if (!positionals.empty()) applyPositionals(positionals, options);
        return options;
    }
    applyPositionals(positionals, options);
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
