#include "render/render_stats.h"

#include "core/atomic_file.h"
#include "render/settings_table.h"

#include <cstdio>
#include <nlohmann/json.hpp>
#include <fstream>
#include <ostream>
#include <stdexcept>
#include <string>
#include <unistd.h>

namespace ray {

namespace {

// "memory       peak 411.2 MB; meshes 1002528 triangles, 60.0 bytes a triangle loaded, 180.0
// packed, 410.1 at peak": where a large mesh's memory goes, against the triangle count.
void printMemory(const RenderStats& s, std::ostream& out) {
    if (s.peakMemoryBytes == 0 && s.meshTriangles == 0) return;
    char part[200];
    std::snprintf(part, sizeof part, "memory       peak %.1f MB", double(s.peakMemoryBytes) / 1e6);
    std::string text = part;
    if (s.meshTriangles > 0) {
        const double n = double(s.meshTriangles);
        std::snprintf(part, sizeof part, "; meshes %llu triangles, %.1f bytes a triangle loaded",
                      (unsigned long long)s.meshTriangles, double(s.meshLoadedBytes) / n);
        text += part;
        if (s.meshPackedBytes > 0) {
            std::snprintf(part, sizeof part, ", %.1f packed", double(s.meshPackedBytes) / n);
            text += part;
        }
        std::snprintf(part, sizeof part, ", %.1f at peak", double(s.peakMemoryBytes) / n);
        text += part;
    }
    out << text << "\n";
}

}  // namespace

void printStats(const RenderStats& s, std::ostream& out) {
    char line[256];
    std::snprintf(line, sizeof line, "image        %d x %d, %d samples/pixel max, depth %d, on %s\n", s.width,
                  s.height, s.samples, s.depth, s.device.c_str());
    out << line;
    std::snprintf(line, sizeof line, "rays         %llu primary, %llu shadow, %llu secondary, %llu total\n",
                  (unsigned long long)s.primaryRays, (unsigned long long)s.shadowRays,
                  (unsigned long long)s.secondaryRays, (unsigned long long)s.totalRays());
    out << line;
    std::snprintf(line, sizeof line,
                  "time         load %.3f s, BVH build %.3f s, kernel build %.3f s, render %.3f s\n",
                  s.loadSeconds, s.bvhBuildSeconds, s.kernelBuildSeconds, s.renderSeconds);
    out << line;
    std::snprintf(line, sizeof line, "speed        %.2f Mrays/s\n", s.mraysPerSecond());
    out << line;
    printMemory(s, out);
    const DistributionStats& mpi = s.distribution;
    if (mpi.ranks > 0) {
        std::string perRank;
        for (int tiles : mpi.tilesPerRank) {
            if (!perRank.empty()) perRank += '/';
            perRank += std::to_string(tiles);
        }
        std::snprintf(line, sizeof line,
                      "mpi          %d ranks, %d tiles (%s by rank), rank 0 handled %llu messages, %.2f MB, "
                      "in %.3f s (%.3f ms a tile)\n",
                      mpi.ranks, mpi.tiles, perRank.c_str(), (unsigned long long)mpi.messages, double(mpi.bytes) / 1e6,
                      mpi.dispatchSeconds, mpi.dispatchMillisecondsPerTile());
        out << line;
    }
    // Several devices (or ranks): each one's share of the frame.
    if (s.devices.size() < 2) return;
    for (size_t i = 0; i < s.devices.size(); ++i) {
        const DeviceStats& d = s.devices[i];
        std::string who = i < s.deviceRanks.size() ? "rank " + std::to_string(s.deviceRanks[i]) + " " : "";
        std::snprintf(line, sizeof line, "device       %s%s: %d tiles, %llu pixels, %llu rays, busy %.3f s, %.2f Mrays/s%s\n",
                      who.c_str(), d.device.c_str(), d.tiles, (unsigned long long)d.pixels, (unsigned long long)d.rays,
                      d.busySeconds, d.mraysPerSecond(),
                      d.failed ? " (failed, dropped)" : d.building ? " (still building its kernel)" : "");
        out << line;
    }
}

std::string statsToJson(const RenderStats& s, const RenderSettings& settings) {
    // ordered_json keeps the keys in the order written here, the order scripts have seen.
    nlohmann::ordered_json json;
    json["width"] = s.width;
    json["height"] = s.height;
    json["samples"] = s.samples;
    json["depth"] = s.depth;
    json["device"] = s.device;
    json["primary_rays"] = s.primaryRays;
    json["shadow_rays"] = s.shadowRays;
    json["secondary_rays"] = s.secondaryRays;
    json["total_rays"] = s.totalRays();
    json["load_seconds"] = s.loadSeconds;
    json["bvh_build_seconds"] = s.bvhBuildSeconds;
    json["kernel_build_seconds"] = s.kernelBuildSeconds;
    json["render_seconds"] = s.renderSeconds;
    json["upload_seconds"] = s.uploadSeconds;
    json["mrays_per_second"] = s.mraysPerSecond();
    json["peak_memory_bytes"] = s.peakMemoryBytes;
    json["mesh_triangles"] = s.meshTriangles;
    json["mesh_loaded_bytes"] = s.meshLoadedBytes;
    json["mesh_packed_bytes"] = s.meshPackedBytes;
    if (s.distribution.ranks > 0) {
        const DistributionStats& mpi = s.distribution;
        json["mpi"] = {{"ranks", mpi.ranks},
                       {"tiles", mpi.tiles},
                       {"tiles_per_rank", mpi.tilesPerRank},
                       {"messages", mpi.messages},
                       {"bytes", mpi.bytes},
                       {"dispatch_seconds", mpi.dispatchSeconds},
                       {"dispatch_ms_per_tile", mpi.dispatchMillisecondsPerTile()}};
    }
    json["devices"] = nlohmann::ordered_json::array();
    for (size_t i = 0; i < s.devices.size(); ++i) {
        const DeviceStats& d = s.devices[i];
        nlohmann::ordered_json device;
        device["device"] = d.device;
        if (i < s.deviceRanks.size()) device["rank"] = s.deviceRanks[i];
        device["tiles"] = d.tiles;
        device["pixels"] = d.pixels;
        device["rays"] = d.rays;
        device["busy_seconds"] = d.busySeconds;
        device["mrays_per_second"] = d.mraysPerSecond();
        device["failed"] = d.failed;
        device["building"] = d.building;
        device["kernel_private_bytes"] = d.kernelPrivateBytes;
        json["devices"].push_back(device);
    }
    // Every render setting the frame was made with, by its table name (the Python keywords).
    for (const SettingSpec& spec : renderSettingsTable())
        json["settings"][std::string(spec.name)] =
            std::visit([](const auto& value) { return nlohmann::ordered_json(value); }, settingValue(settings, spec));
    return json.dump(2) + "\n";
}

void writeStatsJson(const RenderStats& stats, const RenderSettings& settings, const std::filesystem::path& file) {
    writeFileAtomically(file, statsToJson(stats, settings));
}

}  // namespace ray
