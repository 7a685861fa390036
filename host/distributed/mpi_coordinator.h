// Rank 0 of a distributed render (mpi_render.h): it hands the tiles out on demand (the tile
// scheduler, whose workers are here the ranks), renders its own share on its own devices,
// pastes every kept tile into the image, drops the ranks that stop answering (a tile past
// its deadline, or silent, not even a heartbeat, for the usual deadline), then writes the
// image and the statistics and tells every worker how the job ends.
#pragma once

#include <string>
#include <vector>

#include "core/test_hooks.h"
#include "distributed/mpi_startup.h"

namespace ray::mpi {

// The frame across the ranks; the exit code. `hosts`: each rank's host, for the messages;
// `silentAtStart`: the workers that never finished their start-up (startCoordinator),
// already named, which get no tiles and the job ends without. Never returns when the job
// ends by MPI_Abort (a rank stopped answering).
int runCoordinator(Prepared& p, const MpiSession& mpi, std::vector<std::string> hosts,
                   const std::vector<int>& silentAtStart, const TestHooks& hooks);

}  // namespace ray::mpi
