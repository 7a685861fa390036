// `mpirun -n N ray scene.xml [w h] [depth] [options]`: one frame across N processes, on
// one machine or on the hosts of a hostfile (Open MPI; built when CMake finds MPI).
//
// Every rank parses the command line and loads the scene (the same path on every host);
// the ranks agree on the outcome before any rendering, so that a bad scene or option ends
// every rank with one message, from rank 0, and exit code 2. Rank 0 then hands tiles out
// on demand (render/tile_scheduler.h, whose workers are here the ranks) and renders too,
// so that -n 1 works; each rank renders the tiles it is given on its own devices (--device,
// as in one process) through the frame interface (render/frame_source.h, FrameRequest::tiles)
// on the OpenCL engine, several in flight per device, and sends each finished tile to rank 0, which
// alone writes the image, the progress and the statistics (per rank and device). Every
// pixel is a function of its coordinates and the seed only: the image is byte-identical to
// a one-process render.
//
// Failures: a rank whose every device failed reports it and its tiles go to the others
// (a warning names it); any other error on a rank ends the job with MPI_Abort, never a
// hang. mpirun itself ends the job when a rank dies. On Ctrl-C mpirun sends every rank
// SIGTERM: they stop, rank 0 leaves the output untouched (or writes it with --partial).
// A rank that stops (SIGSTOP, a wedged host) is told from a slow one by its heartbeats:
// every worker's main thread beats each second it sends nothing else, from its start-up
// (the scene loads on another thread) to its statistics, compiling included. Rank 0 takes
// a worker silent for the usual deadline (10 s or more) for stopped, whatever it was
// doing: it names it, renders the frame without it and ends the job with exit 4. Hence no
// collective anywhere: a stopped rank would hold the others in it for ever.
//
// Threads: only each rank's main thread calls MPI (MPI_THREAD_FUNNELED): it runs the
// message loop while the engine renders on other threads.
//
// All of it is the module libray_mpi.so, the only code of ray linked with Open MPI: main()
// opens it only when launchedByMpirun() (app/mpi_launch.h) and calls its entry point,
// ray_mpi_main (app/command_module_abi.h), which runs runDistributedCommand.
//
// The parts, each a file of host/distributed/: this entry point; mpi_startup (the start-up
// without a collective, and what it leaves each rank holding), mpi_worker (a worker rank's
// message loop), mpi_coordinator (rank 0: the tiles handed out, its own share, the image,
// the ranks that stop answering), mpi_protocol (the messages and their encoding, and how the
// job ends: MPI_Abort, a worker waiting to be ended, an interrupt).
#pragma once

#include <string>
#include <vector>

namespace ray {

// The render command across the ranks of MPI_COMM_WORLD; the exit code of this rank.
int runDistributedCommand(int argc, char** argv, const std::vector<std::string>& args);

}  // namespace ray
