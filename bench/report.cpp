#include "report.h"

#include <nlohmann/json.hpp>

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

// --- JSON (nlohmann-json; ordered_json keeps the keys in the order written) ------------

using Json = nlohmann::ordered_json;

// A finite number, else null (a run that timed out has no time).
Json number(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }
Json number(const std::optional<double>& value) { return value ? number(*value) : Json(nullptr); }

Json statsJson(const RayStats& s) {
    return Json{{"width", s.width},
                {"height", s.height},
                {"samples", s.samples},
                {"depth", s.depth},
                {"device", s.device},
                {"primary_rays", s.primaryRays},
                {"shadow_rays", s.shadowRays},
                {"secondary_rays", s.secondaryRays},
                {"total_rays", s.totalRays},
                {"load_seconds", number(s.loadSeconds)},
                {"bvh_build_seconds", number(s.bvhBuildSeconds)},
                {"kernel_build_seconds", number(s.kernelBuildSeconds)},
                {"render_seconds", number(s.renderSeconds)},
                {"mrays_per_second", number(s.mraysPerSecond)}};
}

Json runJson(const RunRecord& run) {
    return Json{{"scene", run.scene->name},
                {"file", run.scene->file.string()},
                {"primitives", run.scene->primitives ? Json(*run.scene->primitives) : Json(nullptr)},
                {"device", run.device->label},
                {"device_name", run.device->name},
                {"phase", phaseName(run.phase)},
                {"status", run.status},
                {"wall_seconds", number(run.wallSeconds)},
                {"peak_mib", number(run.peakMiB)},
                {"stats", run.ok() ? statsJson(*run.stats) : Json(nullptr)}};
}

// The render seconds of a run that finished, else null.
Json renderSeconds(const RunRecord* run) {
    return run && run->ok() ? number(run->stats->renderSeconds) : Json(nullptr);
}

Json ratioJson(const BenchResults& results, const RunRecord& warm) {
    const RunRecord* cold = findRun(results, *warm.scene, *warm.device, Phase::Cold);
    const BenchDevice* referenceDev = referenceDevice(results);
    const RunRecord* reference =
        referenceDev ? findRun(results, *warm.scene, *referenceDev, Phase::Reference) : nullptr;
    const BenchDevice* plainDev = referenceDevice(results, true);
    const RunRecord* plain = plainDev ? findRun(results, *warm.scene, *plainDev, Phase::Reference) : nullptr;
    return Json{{"scene", warm.scene->name},
                {"device", warm.device->label},
                {"kernel_render_seconds", number(warm.stats->renderSeconds)},
                {"reference_render_seconds", renderSeconds(reference)},
                {"reference_status", reference ? reference->status : "not run"},
                {"reference_over_kernel", number(speedupOverReference(results, warm))},
                {"plain_reference_render_seconds", renderSeconds(plain)},
                {"plain_reference_status", plain ? plain->status : "not run"},
                {"plain_reference_over_kernel", number(speedupOverReference(results, warm, true))},
                {"kernel_build_cold_seconds",
                 cold && cold->ok() ? number(cold->stats->kernelBuildSeconds) : Json(nullptr)},
                {"kernel_build_warm_seconds", number(warm.stats->kernelBuildSeconds)}};
}

Json settingsJson(const BenchResults& r) {
    return Json{{"width", r.size.width},
                {"height", r.size.height},
                {"depth", r.size.depth},
                {"aa", "off"},
                {"quick", r.quick},
                {"ray_binary", r.rayBinary},
                {"scenes_dir", r.scenesDir},
                {"reference_timeout_seconds", number(r.referenceTimeoutSeconds)},
                {"reference_max_primitives", r.referenceMaxPrimitives},
                {"plain_max_primitives", r.plainMaxPrimitives}};
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
    Json json;
    json["settings"] = settingsJson(results);
    json["devices"] = Json::array();
    for (const BenchDevice& d : results.devices)
        json["devices"].push_back(Json{{"device", d.label}, {"argument", d.argument}, {"name", d.name}});
    json["runs"] = Json::array();
    for (const RunRecord& run : results.runs) json["runs"].push_back(runJson(run));
    json["ratios"] = Json::array();
    for (const RunRecord& run : results.runs)
        if (run.phase == Phase::Warm && run.ok()) json["ratios"].push_back(ratioJson(results, run));
    json["total_wall_seconds"] = number(results.totalWallSeconds);

    std::ofstream stream(file);
    stream << json.dump(2) << "\n";
    if (!stream) throw std::runtime_error(file.string() + ": cannot write the results");
}

}  // namespace bench
