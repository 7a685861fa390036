// The C interface of ray's command modules: libray_viewer.so (`ray view`, host/viewer/) and
// libray_mpi.so (`mpirun -n N ray`, host/distributed/mpi_render.h). ray opens one only for
// its command (app/command_modules.h), so that cpp-httplib with OpenSSL and Open MPI are
// loaded by no other run. Each module exports one entry point with a plain C signature;
// it reports its own failures and returns the command's exit status, never throws.
//
// The modules are no libraries of their own: they use ray's host code from the executable
// that loaded them (it exports its symbols), so they hold no second copy of its globals
// (the interrupt flag, the kernel cache) and work only with the ray they were built with.
#pragma once

extern "C" {

// `ray view ARGS...`: the argc arguments after "view" (argv[argc] is null).
typedef int (*RayViewMain)(int argc, const char* const* argv);
int ray_view_main(int argc, const char* const* argv);

// The render command on this rank of MPI_COMM_WORLD, with main()'s own argc and argv (which
// MPI_Init may read).
typedef int (*RayMpiMain)(int argc, char** argv);
int ray_mpi_main(int argc, char** argv);

}  // extern "C"

// The exported symbol names, one per typedef above.
#define RAY_VIEW_MAIN "ray_view_main"
#define RAY_MPI_MAIN "ray_mpi_main"
