#include "app/cli.h"

#include "render/renderer.h"

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <functional>
#include <sstream>

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
  --dof MODE               depth of field for cameras with an aperture: course (default;
                           each sample averages 25 rays from a 5x5 grid of lens points,
                           as the course renders it) | disk (one random lens point a
                           sample: a smooth blur with --aa stratified and many samples)
  --fresnel                weight the reflection and transmission of transparent objects
                           by exact Fresnel, reflections kept inside the object (SPEC §4;
                           off by default)
  --course-meshes          measure mesh hits as the course's solution did: distance along
                           the normalized object-space ray (t·|M⁻¹d|), hit point placed
                           there, face normals (README "Conventions"; off by default)
  --texture-filter F       nearest (default, as the course) | bilinear | trilinear |
                           course (bilinear with texel corners at integers, as the
                           course's renders made with its texture filter on)
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

across processes and machines (a build with MPI): mpirun [-q] -n N [--hostfile F] ray
<scene.xml> ... renders one frame on N ranks, each on its own --device; rank 0 hands out
the tiles, renders too and alone writes the image and the statistics (see README.md)
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

std::string formatNumber(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
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

double parseDoubleBetween(const std::string& text, const std::string& what, double lo, double hi) {
    const double value = parseDouble(text, what);
    if (!(value >= lo && value <= hi))
        throw UsageError(what + " must be between " + formatNumber(lo) + " and " + formatNumber(hi));
    return value;
}

AntialiasMode parseAntialias(const std::string& text) {
    if (text == "off") return AntialiasMode::Off;
    if (text == "course") return AntialiasMode::Course;
    if (text == "stratified") return AntialiasMode::Stratified;
    if (text == "adaptive") return AntialiasMode::Adaptive;
    throw UsageError("--aa must be off, course, stratified or adaptive, not '" + text + "'");
}

DofMode parseDofMode(const std::string& text) {
    if (text == "course") return DofMode::Course;
    if (text == "disk") return DofMode::Disk;
    throw UsageError("--dof must be course or disk, not '" + text + "'");
}

TextureFilter parseTextureFilter(const std::string& text) {
    if (text == "nearest") return TextureFilter::Nearest;
    if (text == "bilinear") return TextureFilter::Bilinear;
    if (text == "trilinear") return TextureFilter::Trilinear;
    if (text == "course") return TextureFilter::Course;
    throw UsageError("--texture-filter must be nearest, bilinear, trilinear or course, not '" + text + "'");
}

void validateDevice(const std::string& text) {
    if (!isDeviceSelection(text))
        throw UsageError("--device must be auto, cpu, gpu, all, ref, a device index or a list such as 0,2, not '" +
                         text + "'");
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

namespace {

// The option table. Each option is one line: its names, and what its value does to the
// options (the converters above keep ray's messages). To add an option, add a line here and
// its entry in kUsageText. CLI11 does the matching: names, values, repeats, unknown options.
void addOptions(CLI::App& app, CliOptions& options) {
    RenderSettings& s = options.settings;
    auto text = [&](const char* names, std::function<void(const std::string&)> apply) {
        return app.add_option_function<std::string>(names, std::move(apply))->take_last();
    };
    auto flag = [&](const char* names, bool& target, bool value) {
        return app.add_flag_callback(names, [&target, value] { target = value; });
    };
    flag("-h,--help", options.help, true);
    flag("--version", options.version, true);
    text("-o,--output", [&](const std::string& v) { options.output = v; });
    text("--aa", [&](const std::string& v) { s.antialias = parseAntialias(v); });
    text("--samples", [&](const std::string& v) { s.samples = parseInt(v, "--samples", 1, kMaxSamples); });
    text("--area-samples",
         [&](const std::string& v) { s.areaSamples = parseInt(v, "--area-samples", 1, kMaxAreaSamples); });
    text("--seed", [&](const std::string& v) { s.seed = uint32_t(parseInt(v, "--seed", 0, 2147483647)); });
    text("--shutter", [&](const std::string& v) { s.shutter = parseDoubleBetween(v, "--shutter", 0, 1); });
    text("--threshold", [&](const std::string& v) { s.weightThreshold = parseDoubleBetween(v, "--threshold", 0, 1); });
    text("--device", [&](const std::string& v) { validateDevice(v); options.device = v; });
    flag("--list-devices", options.listDevices, true);
    text("--tile-size", [&](const std::string& v) { options.tileSize = parseInt(v, "--tile-size", 8, 4096); });
    flag("--no-bvh", options.referenceBruteForce, true);
    app.add_option_function<std::vector<std::string>>("--search-path", [&](const std::vector<std::string>& dirs) {
        for (const std::string& dir : dirs) options.searchPaths.emplace_back(dir);
    })->expected(1)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    flag("--strict", options.strict, true);
    flag("--no-shadows", s.shadows, false);
    flag("--no-reflections", s.reflections, false);
    flag("--no-refraction", s.refraction, false);
    flag("--no-textures", s.textures, false);
    flag("--no-dof", s.depthOfField, false);
    text("--dof", [&](const std::string& v) { s.dofMode = parseDofMode(v); });
    flag("--fresnel", s.fresnel, true);
    flag("--course-meshes", s.courseMeshes, true);
    text("--texture-filter", [&](const std::string& v) { s.textureFilter = parseTextureFilter(v); });
    flag("-q,--quiet", options.quiet, true);
    flag("--stats", options.stats, true);
    text("--stats-json", [&](const std::string& v) { options.statsJson = v; });
    flag("--partial", options.partial, true);
    text("--max-primitives",
         [&](const std::string& v) { options.maxPrimitives = size_t(parseInt(v, "--max-primitives", 1, 2147483647)); });
}

// CLI11's own errors in ray's words (the tests and scripts match on these).
UsageError usageErrorFrom(const CLI::ParseError& error, const CLI::App& app) {
    if (dynamic_cast<const CLI::ExtrasError*>(&error)) {
        const std::vector<std::string> extras = app.remaining();
        const std::string first = extras.empty() ? std::string() : extras.front();
        return UsageError("unknown option '" + first + "'");
    }
    const std::string message = error.what();
    if (dynamic_cast<const CLI::ArgumentMismatch*>(&error)) {
        // CLI11 names the option before the first ':' ("--output: 1 required TEXT missing").
        return UsageError(message.substr(0, message.find(':')) + " needs a value");
    }
    return UsageError(message);
}

}  // namespace

CliOptions parseCommandLine(const std::vector<std::string>& args) {
    CliOptions options;
    std::vector<std::string> positionals;
    CLI::App app("ray", "ray");
    app.set_help_flag();  // ray prints its own kUsageText for -h/--help
    addOptions(app, options);
    app.add_option("positionals", positionals);  // <scene.xml> [<width> <height>] [<depth>]

    // CLI11 takes a vector in reverse order (it pops arguments off the back).
    std::vector<std::string> reversed(args.rbegin(), args.rend());
    try {
        app.parse(reversed);
    } catch (const CLI::ParseError& e) {
        throw usageErrorFrom(e, app);
    }
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
