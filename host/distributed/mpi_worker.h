// A worker rank (1..N-1) of a distributed render (mpi_render.h): its main thread runs the
// message loop (asks rank 0 for tiles as its devices wait for them, sends each finished tile
// and a heartbeat each second it sends nothing else, then its statistics) while the engine
// renders the tiles on other threads, through the frame interface.
#pragma once

#include "core/test_hooks.h"
#include "distributed/mpi_startup.h"

namespace ray::mpi {

// Renders the tiles rank 0 hands out; returns the exit code rank 0 decides (kEnd), or never
// returns when the job ends by MPI_Abort.
int runWorker(Prepared& p, const TestHooks& hooks);

// The test hooks that make a worker stop itself (core/test_hooks.h; tests/mpi.sh) do it
// with SIGSTOP, as a wedged host stops answering without dying, and say when on stderr:
// in its start-up (stopWhileLoadingSeconds: its main thread beating meanwhile, before it
// tells rank 0 how the start-up went), once it has sent some tiles (a rank hung mid-frame),
// or some seconds into its message loop (with slowBuild, a rank stopped while it compiles).
void stopThisRank();

}  // namespace ray::mpi
