// The start-up of a distributed render (mpi_render.h), without a collective: a rank stopped
// before a collective would hold every other rank in it for ever. Each worker prepares
// (parses the command line, loads the scene, opens its devices) on another thread while its
// main thread sends heartbeats, then says hello to rank 0: its outcome, fingerprint and
// host. Rank 0 decides for every rank (kStart) once each worker has said hello or has been
// silent for the usual deadline. Also what the start-up leaves each rank holding (Prepared)
// and the rank's frame it renders with it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/cli.h"
#include "core/test_hooks.h"
#include "opencl/opencl_device.h"
#include "opencl/opencl_frame_source.h"
#include "render/frame_source.h"
#include "scene/scene.h"

namespace ray::mpi {

// MPI_Init_thread and MPI_Finalize; only the main thread calls MPI (MPI_THREAD_FUNNELED).
struct MpiSession {
    int rank = 0, size = 1;
    MpiSession(int argc, char** argv);
    ~MpiSession();
};

// What every rank holds once the command line and the scene are loaded.
struct Prepared {
    CliOptions options;
    std::filesystem::path output;  // rank 0
    std::shared_ptr<const Scene> scene;  // shared with each frame source that renders it
    std::vector<OpenClDevice> devices;
    double loadSeconds = 0;
    bool nothingToRender = false;  // --help, --version, --list-devices
    uint64_t fingerprint = 0;      // of the command line and the scene file; 0 until loaded
};

// A worker's start-up; the exit code to end with, 0 to render.
int startWorker(Prepared& p, const std::vector<std::string>& args, int rank, const TestHooks& hooks);

// Rank 0's start-up: the exit code every rank ends with (0: render), each rank's host, and
// the workers that never said hello (named; the frame goes on without them). When the
// start fails, the first rank that failed (in rank order) says why, through rank 0 alone.
int startCoordinator(Prepared& p, const std::vector<std::string>& args, const MpiSession& mpi,
                     std::vector<std::string>& hosts, std::vector<int>& silent, const TestHooks& hooks);

// The side of the frame's tiles: rank 0 cuts the image by it, every rank's devices check
// their limits with it. Every rank computes the same from the same command line and scene.
int tileSideOf(const Prepared& p);

// A rank's frame (render/frame_source.h): the tiles admitted from `tiles`, each finished one
// to `onTile`; the image the source assembles is not used (rank 0 pastes the kept tiles).
FrameRequest frameRequest(const Prepared& p, TileSource& tiles, std::function<void(const FinishedTile&)> onTile);

// One frame of the rank's share on its own devices.
RenderStats renderShare(OpenClFrameSource& frames, const Prepared& p, const FrameRequest& request);

}  // namespace ray::mpi
