// What a render did: rays by kind and timings, for --stats and --stats-json.
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "render/render_settings.h"

namespace ray {

// One OpenCL device's share of a frame rendered on several.
struct DeviceStats {
    std::string device;  // "NAME (PLATFORM)"
    int tiles = 0;       // kept (a duplicate dropped at the end of a frame is not counted)
    uint64_t pixels = 0, rays = 0;
    double busySeconds = 0;  // from its first launch to its last tile of the frame
    bool failed = false;
    std::string failure;  // why it was dropped
    bool building = false;  // still building its kernel when the frame was done: took no part
    uint64_t kernelPrivateBytes = 0;  // the driver's CL_KERNEL_PRIVATE_MEM_SIZE, once it rendered

    double mraysPerSecond() const { return busySeconds > 0 ? double(rays) / busySeconds / 1e6 : 0; }
};

// A frame rendered across the ranks of mpirun (distributed/mpi_render.h): the work each
// rank did and what handing it out cost rank 0.
struct DistributionStats {
    int ranks = 0;  // 0: rendered in one process
    int tiles = 0;
    std::vector<int> tilesPerRank;      // kept from each rank
    uint64_t messages = 0, bytes = 0;   // sent and received by rank 0
    double dispatchSeconds = 0;         // rank 0's time spent handling them

    double dispatchMillisecondsPerTile() const { return tiles > 0 ? dispatchSeconds * 1e3 / tiles : 0; }
};

// How a frame got the scene's packed tables (the OpenCL engine keeps them from frame to
// frame, opencl/packed_scene_cache.h): what an edit cost the next frame.
struct SceneUpdateStats {
    // "none": the tables packed for an earlier frame, kept whole (or no packing: the host
    // renderer); "edit": re-packed as the edits' change sets said (scene/scene_changes.h);
    // "compared": re-packed after comparing the scenes (a file reloaded from disk);
    // "full": packed whole (the first frame, a change of shape).
    std::string packing = "none";
    // The BVH: "kept", "refit" (moved primitives, the tree's shape kept) or "rebuilt".
    std::string bvh = "kept";
    // The tables given new contents, by their names in cl/shared_types.h RAY_SCENE_BUFFERS
    // ("materials"): each device uploads these again, and only these.
    std::vector<std::string> tables;
};

struct RenderStats {
    int width = 0, height = 0, samples = 0, depth = 0;
    std::string device;
    uint64_t primaryRays = 0, shadowRays = 0, secondaryRays = 0;
    double loadSeconds = 0, bvhBuildSeconds = 0, kernelBuildSeconds = 0, renderSeconds = 0;
    double uploadSeconds = 0;
    double packSeconds = 0;  // OpenCL: packing the scene, when the frame (re)packed (the API's; not printed)
    SceneUpdateStats sceneUpdate;  // OpenCL: what the frame re-packed and re-uploaded
    // OpenCL: every device of the selection; the distributed render adds a rank to each.
    std::vector<DeviceStats> devices;
    std::vector<int> deviceRanks;  // parallel to devices when rendered through MPI, else empty
    std::vector<std::string> warnings;  // devices dropped
    DistributionStats distribution;
    // Memory: the process's peak resident size (getrusage, at the end of the frame); the
    // meshes' triangles (each mesh once, however many instances use it), what they took
    // as loaded (positions, normals, texture coordinates, corners) and, on OpenCL devices,
    // as packed (their BVH nodes, triangle and shading records) when the frame packed them.
    uint64_t peakMemoryBytes = 0;
    uint64_t meshTriangles = 0, meshLoadedBytes = 0, meshPackedBytes = 0;

    uint64_t totalRays() const { return primaryRays + shadowRays + secondaryRays; }
    double mraysPerSecond() const { return renderSeconds > 0 ? double(totalRays()) / renderSeconds / 1e6 : 0; }
};

void printStats(const RenderStats& stats, std::ostream& out);
// The statistics, then "settings": every render setting by its table name
// (render/settings_table.h), as the frame was made.
std::string statsToJson(const RenderStats& stats, const RenderSettings& settings);
// Written atomically (core/atomic_file.h). Throws FileWriteError (a std::runtime_error).
void writeStatsJson(const RenderStats& stats, const RenderSettings& settings, const std::filesystem::path& file);

}  // namespace ray
