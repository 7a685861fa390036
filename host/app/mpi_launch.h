// Whether ray was started by mpirun, from the launcher's environment variables alone: main()
// asks before anything else, and opens the MPI module (libray_mpi.so, mpi_render.h) only
// when it was. No MPI here, so that every other run of ray loads none.
#pragma once

namespace ray {

// Whether this process was started by mpirun (Open MPI's or a PMI launcher's variables).
bool launchedByMpirun();

// This process's rank in MPI_COMM_WORLD as the launcher set it, before MPI starts; -1 when
// no launcher said.
int launcherRank();

}  // namespace ray
