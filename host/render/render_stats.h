// What a render did: rays by kind and timings, for --stats and --stats-json.
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>

namespace ray {

struct RenderStats {
    int width = 0, height = 0, samples = 0, depth = 0;
    std::string device;
    uint64_t primaryRays = 0, shadowRays = 0, secondaryRays = 0;
    double loadSeconds = 0, bvhBuildSeconds = 0, kernelBuildSeconds = 0, renderSeconds = 0;

    uint64_t totalRays() const { return primaryRays + shadowRays + secondaryRays; }
    double mraysPerSecond() const { return renderSeconds > 0 ? double(totalRays()) / renderSeconds / 1e6 : 0; }
};

void printStats(const RenderStats& stats, std::ostream& out);
std::string statsToJson(const RenderStats& stats);
// Written atomically (core/atomic_file.h). Throws FileWriteError (a std::runtime_error).
void writeStatsJson(const RenderStats& stats, const std::filesystem::path& file);

}  // namespace ray
