// One render by the `ray` binary, run as a child process, and what it reports: its own
// --stats-json figures plus what the bench measures from outside (wall time, peak memory).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace bench {

// The fields of `ray --stats-json` (host/render/render_stats.cpp).
struct RayStats {
    int width = 0, height = 0, samples = 0, depth = 0;
    std::string device;
    uint64_t primaryRays = 0, shadowRays = 0, secondaryRays = 0, totalRays = 0;
    double loadSeconds = 0, bvhBuildSeconds = 0, kernelBuildSeconds = 0, renderSeconds = 0;
    double mraysPerSecond = 0;
};

std::optional<RayStats> readStatsJson(const std::filesystem::path& file);

// Cold: the kernel compiled from source into an empty cache; warm: the same cache again,
// so the compiled binary is reused; reference: the host renderer, no kernel at all.
enum class Phase { Cold, Warm, Reference };
const char* phaseName(Phase phase);

struct BenchScene {
    std::string name;                      // file stem: "chess", "spheres_1e4"
    std::filesystem::path file;
    std::optional<uint64_t> primitives;    // nullopt when it could not be counted
    int sphereLevels = 0;                  // k for the generated 10^k-sphere scenes, else 0
    // Sampling and feature options for ray; empty means "--aa off" (the feature rows set
    // their own, e.g. "--aa adaptive --samples 16").
    std::vector<std::string> rayOptions;
    bool plainReference = false;  // the plain reference (no BVH) may run it: corpus and spheres
};

struct BenchDevice {
    std::string argument;  // what --device gets: an index, or "ref"
    std::string label;     // short name for the table: "cl0", "ref", "plain"
    std::string name;      // as --list-devices names it
    // More arguments for ray: {"--no-bvh"} makes the reference renderer the plain oracle
    // that tests every primitive for every ray.
    std::vector<std::string> extraArguments;
    bool isReference() const { return argument == "ref"; }
    bool isPlainReference() const { return isReference() && !extraArguments.empty(); }
};

struct RunRecord {
    const BenchScene* scene = nullptr;
    const BenchDevice* device = nullptr;
    Phase phase = Phase::Reference;
    std::string status;                 // "ok", "timeout", "exit 3", "skipped (...)"
    std::optional<RayStats> stats;      // present when status is "ok"
    double wallSeconds = 0;
    double peakMiB = 0;
    bool ok() const { return status == "ok" && stats.has_value(); }
};

struct RenderSize {
    int width = 1024, height = 768, depth = 4;
};

struct RayInvocation {
    std::filesystem::path rayBinary;
    std::filesystem::path workDir;   // receives the image, the statistics and the log
    std::filesystem::path cacheDir;  // kernel caches (empty for the reference renderer)
    RenderSize size;
    double timeoutSeconds = 0;
};

RunRecord runRay(const RayInvocation& invocation, const BenchScene& scene, const BenchDevice& device,
                 Phase phase);

// The OpenCL devices `ray --list-devices` names ("N: name" lines).
std::vector<BenchDevice> listOpenClDevices(const std::filesystem::path& rayBinary,
                                           const std::filesystem::path& workDir);

}  // namespace bench
