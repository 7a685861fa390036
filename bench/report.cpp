#include "report.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace bench {

namespace fs = std::filesystem;

namespace {

const RunRecord* findRun(const BenchResults& results, const BenchScene& scene, const BenchDevice& device,
                         Phase phase) {
    for (const RunRecord& run : results.runs)
        if (run.scene == &scene && run.device == &device && run.phase == phase) return &run;
    return nullptr;
}

// The run whose speed is reported for a device: the warm one for OpenCL (the cold one's
// render also pays for the driver's lazy compile), the only one for the reference.
const RunRecord* reportedRun(const BenchResults& results, const BenchScene& scene, const BenchDevice& device) {
    return findRun(results, scene, device, device.isReference() ? Phase::Reference : Phase::Warm);
}

// The reference renderer as it renders by default (with its BVH), or its plain form.
const BenchDevice* referenceDevice(const BenchResults& results, bool plain = false) {
    for (const BenchDevice& device : results.devices)
        if (device.isReference() && device.isPlainReference() == plain) return &device;
    return nullptr;
}

// How many times faster than the reference renderer (or its plain form) a kernel run
// rendered the same scene (render_seconds only: loading and building are not the
// kernel's work).
std::optional<double> speedupOverReference(const BenchResults& results, const RunRecord& run, bool plain = false) {
    const BenchDevice* reference = referenceDevice(results, plain);
    if (!reference || run.device->isReference() || !run.ok()) return std::nullopt;
    const RunRecord* referenceRun = findRun(results, *run.scene, *reference, Phase::Reference);
    if (!referenceRun || !referenceRun->ok() || run.stats->renderSeconds <= 0) return std::nullopt;
    return referenceRun->stats->renderSeconds / run.stats->renderSeconds;
}

std::string formatted(const char* format, double value) {
    char text[64];
    std::snprintf(text, sizeof text, format, value);
    return text;
}

std::string primitivesText(const BenchScene& scene) {
    return scene.primitives ? std::to_string(*scene.primitives) : "?";
}

std::string kernelBuildText(const BenchResults& results, const BenchScene& scene, const BenchDevice& device) {
    if (device.isReference()) return "-";
    const RunRecord* cold = findRun(results, scene, device, Phase::Cold);
    const RunRecord* warm = findRun(results, scene, device, Phase::Warm);
    auto seconds = [](const RunRecord* run) {
        return run && run->ok() ? formatted("%.3f", run->stats->kernelBuildSeconds) : std::string("?");
    };
    return seconds(cold) + "/" + seconds(warm);
}

void printTableHeader(std::ostream& out) {
    char line[256];
    std::snprintf(line, sizeof line, "%-20s %-5s %8s %9s %10s %10s %7s %9s %7s %13s %8s %6s %7s %7s\n", "scene",
                  "dev", "prims", "primary", "shadow", "secondary", "Mray/s", "render s", "BVH s",
                  "kbuild c/w s", "peak MiB", "x ref", "x plain", "wall s");
    out << line << std::string(std::string(line).size() - 1, '-') << "\n";
}

void printTableRow(const BenchResults& results, const BenchScene& scene, const BenchDevice& device,
                   std::ostream& out) {
    const RunRecord* run = reportedRun(results, scene, device);
    // The plain reference's rows only where it applies (the corpus and sphere scenes).
    if (device.isPlainReference() && run && run->status.rfind("not run", 0) == 0) return;
    char line[320];
    if (!run || !run->ok()) {
        std::snprintf(line, sizeof line, "%-20s %-5s %8s   %s\n", scene.name.c_str(), device.label.c_str(),
                      primitivesText(scene).c_str(), run ? run->status.c_str() : "not run");
        out << line;
        return;
    }
    const RayStats& s = *run->stats;
    std::optional<double> speedup = speedupOverReference(results, *run);
    std::optional<double> plainSpeedup = speedupOverReference(results, *run, true);
    std::snprintf(line, sizeof line,
                  "%-20s %-5s %8s %9llu %10llu %10llu %7.2f %9.3f %7.3f %13s %8.1f %6s %7s %7.2f\n",
                  scene.name.c_str(), device.label.c_str(), primitivesText(scene).c_str(),
                  (unsigned long long)s.primaryRays, (unsigned long long)s.shadowRays,
                  (unsigned long long)s.secondaryRays, s.mraysPerSecond, s.renderSeconds, s.bvhBuildSeconds,
                  kernelBuildText(results, scene, device).c_str(), run->peakMiB,
                  speedup ? formatted("%.2f", *speedup).c_str() : "-",
                  plainSpeedup ? formatted("%.1f", *plainSpeedup).c_str() : "-", run->wallSeconds);
    out << line;
}

const BenchScene* sphereScene(const BenchResults& results, int levels) {
    for (const BenchScene& scene : results.scenes)
        if (scene.sphereLevels == levels) return &scene;
    return nullptr;
}

// The baseline of the scaling curve: 10^3 spheres, as log10 n = 3.
constexpr int kBaselineLevels = 3;

double nanosecondsPerRay(const RayStats& s) {
    return s.totalRays ? s.renderSeconds * 1e9 / double(s.totalRays) : 0;
}

void printScalingForDevice(const BenchResults& results, const BenchDevice& device, std::ostream& out) {
    const BenchScene* baselineScene = sphereScene(results, kBaselineLevels);
    const RunRecord* baseline = baselineScene ? reportedRun(results, *baselineScene, device) : nullptr;
    if (!baseline || !baseline->ok()) {
        out << "\n" << device.label << ": no curve, its 10^3-sphere run is "
            << (baseline ? baseline->status : std::string("missing")) << "\n";
        return;
    }
    const RayStats& b = *baseline->stats;
    out << "\n" << device.label << " (" << device.name << ")\n";
    char line[256];
    std::snprintf(line, sizeof line, "%9s %10s %9s %9s %11s %9s %9s %11s\n", "spheres", "render s", "growth",
                  "log n/3", "growth/log", "ns/ray", "growth", "growth/log");
    out << line;
    for (const BenchScene& scene : results.scenes) {
        if (scene.sphereLevels == 0) continue;
        const RunRecord* run = reportedRun(results, scene, device);
        if (!run || !run->ok()) {
            std::snprintf(line, sizeof line, "%9.0e   %s\n", std::pow(10.0, scene.sphereLevels),
                          run ? run->status.c_str() : "not run");
            out << line;
            continue;
        }
        const RayStats& s = *run->stats;
        double logGrowth = double(scene.sphereLevels) / kBaselineLevels;
        double renderGrowth = s.renderSeconds / b.renderSeconds;
        double perRayGrowth = nanosecondsPerRay(s) / nanosecondsPerRay(b);
        std::snprintf(line, sizeof line, "%9.0e %10.3f %9.2f %9.2f %11.2f %9.1f %9.2f %11.2f\n",
                      std::pow(10.0, scene.sphereLevels), s.renderSeconds, renderGrowth, logGrowth,
                      renderGrowth / logGrowth, nanosecondsPerRay(s), perRayGrowth, perRayGrowth / logGrowth);
        out << line;
    }
}

// --- JSON -------------------------------------------------------------------------------

std::string jsonString(const std::string& text) {
    std::string out = "\"";
    for (char c : text) {
        if (c == '"' || c == '\\') out += '\\', out += c;
        else if (static_cast<unsigned char>(c) < 0x20) out += formatted("\\u%04x", double(int(c)));
        else out += c;
    }
    return out + "\"";
}

std::string jsonNumber(double value) {
    return std::isfinite(value) ? formatted("%.6g", value) : "null";
}

std::string statsJson(const RayStats& s) {
    std::ostringstream o;
    o << "{\"width\": " << s.width << ", \"height\": " << s.height << ", \"samples\": " << s.samples
      << ", \"depth\": " << s.depth << ", \"device\": " << jsonString(s.device)
      << ", \"primary_rays\": " << s.primaryRays << ", \"shadow_rays\": " << s.shadowRays
      << ", \"secondary_rays\": " << s.secondaryRays << ", \"total_rays\": " << s.totalRays
      << ", \"load_seconds\": " << jsonNumber(s.loadSeconds)
      << ", \"bvh_build_seconds\": " << jsonNumber(s.bvhBuildSeconds)
      << ", \"kernel_build_seconds\": " << jsonNumber(s.kernelBuildSeconds)
      << ", \"render_seconds\": " << jsonNumber(s.renderSeconds)
      << ", \"mrays_per_second\": " << jsonNumber(s.mraysPerSecond) << "}";
    return o.str();
}

std::string runJson(const RunRecord& run) {
    std::ostringstream o;
    o << "{\"scene\": " << jsonString(run.scene->name) << ", \"file\": " << jsonString(run.scene->file.string())
      << ", \"primitives\": " << (run.scene->primitives ? std::to_string(*run.scene->primitives) : "null")
      << ", \"device\": " << jsonString(run.device->label) << ", \"device_name\": " << jsonString(run.device->name)
      << ", \"phase\": " << jsonString(phaseName(run.phase)) << ", \"status\": " << jsonString(run.status)
      << ", \"wall_seconds\": " << jsonNumber(run.wallSeconds) << ", \"peak_mib\": " << jsonNumber(run.peakMiB)
      << ", \"stats\": " << (run.ok() ? statsJson(*run.stats) : "null") << "}";
    return o.str();
}

std::string ratioJson(const BenchResults& results, const RunRecord& warm) {
    const RunRecord* cold = findRun(results, *warm.scene, *warm.device, Phase::Cold);
    const BenchDevice* referenceDev = referenceDevice(results);
    const RunRecord* reference =
        referenceDev ? findRun(results, *warm.scene, *referenceDev, Phase::Reference) : nullptr;
    std::optional<double> speedup = speedupOverReference(results, warm);
    const BenchDevice* plainDev = referenceDevice(results, true);
    const RunRecord* plain = plainDev ? findRun(results, *warm.scene, *plainDev, Phase::Reference) : nullptr;
    std::optional<double> plainSpeedup = speedupOverReference(results, warm, true);
    std::ostringstream o;
    o << "{\"scene\": " << jsonString(warm.scene->name) << ", \"device\": " << jsonString(warm.device->label)
      << ", \"kernel_render_seconds\": " << jsonNumber(warm.stats->renderSeconds)
      << ", \"reference_render_seconds\": "
      << (reference && reference->ok() ? jsonNumber(reference->stats->renderSeconds) : "null")
      << ", \"reference_status\": " << jsonString(reference ? reference->status : "not run")
      << ", \"reference_over_kernel\": " << (speedup ? jsonNumber(*speedup) : "null")
      << ", \"plain_reference_render_seconds\": "
      << (plain && plain->ok() ? jsonNumber(plain->stats->renderSeconds) : "null")
      << ", \"plain_reference_status\": " << jsonString(plain ? plain->status : "not run")
      << ", \"plain_reference_over_kernel\": " << (plainSpeedup ? jsonNumber(*plainSpeedup) : "null")
      << ", \"kernel_build_cold_seconds\": "
      << (cold && cold->ok() ? jsonNumber(cold->stats->kernelBuildSeconds) : "null")
      << ", \"kernel_build_warm_seconds\": " << jsonNumber(warm.stats->kernelBuildSeconds) << "}";
    return o.str();
}

template <typename Item, typename ToJson>
void writeArray(std::ostream& out, const std::vector<Item>& items, ToJson toJson) {
    out << "[";
    for (size_t i = 0; i < items.size(); ++i) out << (i ? ",\n    " : "\n    ") << toJson(items[i]);
    out << (items.empty() ? "]" : "\n  ]");
}

std::string settingsJson(const BenchResults& r) {
    std::ostringstream o;
    o << "{\"width\": " << r.size.width << ", \"height\": " << r.size.height << ", \"depth\": " << r.size.depth
      << ", \"aa\": \"off\", \"quick\": " << (r.quick ? "true" : "false")
      << ", \"ray_binary\": " << jsonString(r.rayBinary) << ", \"scenes_dir\": " << jsonString(r.scenesDir)
      << ", \"reference_timeout_seconds\": " << jsonNumber(r.referenceTimeoutSeconds)
      << ", \"reference_max_primitives\": " << r.referenceMaxPrimitives
      << ", \"plain_max_primitives\": " << r.plainMaxPrimitives << "}";
    return o.str();
}

}  // namespace

void printRunTable(const BenchResults& results, std::ostream& out) {
    out << "\nray_bench: " << results.size.width << "x" << results.size.height << ", depth "
        << results.size.depth << ", --aa off" << (results.quick ? " (quick)" : "") << "\n";
    for (const BenchDevice& device : results.devices)
        out << "  " << device.label << " = " << device.name << "\n";
    out << "OpenCL rows: the warm run (kernel binary cached); kbuild c/w = kernel build seconds cold/warm;\n"
           "x ref = reference render s / this render s; x plain = the same against the plain reference\n"
           "(no BVH: every primitive for every ray); peak MiB = the child's max RSS\n\n";
    printTableHeader(out);
    for (const BenchScene& scene : results.scenes)
        for (const BenchDevice& device : results.devices) printTableRow(results, scene, device, out);
    out << "\ntotal wall " << formatted("%.1f", results.totalWallSeconds) << " s\n";
}

void printSphereScaling(const BenchResults& results, std::ostream& out) {
    out << "\nSphere scaling (render seconds; growth = value / value at 10^3, log n/3 = log10(n)/3;\n"
           "growth/log stays near 1 when the cost grows like log n; ns/ray = render s / total rays)\n";
    for (const BenchDevice& device : results.devices)
        if (!device.isPlainReference()) printScalingForDevice(results, device, out);  // it runs too few
}

void writeResultsJson(const BenchResults& results, const fs::path& file) {
    std::vector<const RunRecord*> warmRuns;
    for (const RunRecord& run : results.runs)
        if (run.phase == Phase::Warm && run.ok()) warmRuns.push_back(&run);

    std::ostringstream out;
    out << "{\n  \"settings\": " << settingsJson(results) << ",\n  \"devices\": ";
    writeArray(out, results.devices, [](const BenchDevice& d) {
        return "{\"device\": " + jsonString(d.label) + ", \"argument\": " + jsonString(d.argument) +
               ", \"name\": " + jsonString(d.name) + "}";
    });
    out << ",\n  \"runs\": ";
    writeArray(out, results.runs, runJson);
    out << ",\n  \"ratios\": ";
    writeArray(out, warmRuns, [&](const RunRecord* run) { return ratioJson(results, *run); });
    out << ",\n  \"total_wall_seconds\": " << jsonNumber(results.totalWallSeconds) << "\n}\n";

    std::ofstream stream(file);
    stream << out.str();
    if (!stream) throw std::runtime_error(file.string() + ": cannot write the results");
}

}  // namespace bench
