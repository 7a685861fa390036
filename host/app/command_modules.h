// `ray view` and `mpirun -n N ray` run from modules of their own (command_module_abi.h), so
// that their libraries, cpp-httplib with OpenSSL and Open MPI, are loaded by those runs
// alone: together they added 5.3 MB and their relocations to the start of every render.
// These open the module and call its entry point; when it cannot be found or loaded they
// print one message (what is missing, where ray looked, what to do) and return exit code 3.
#pragma once

#include <string>
#include <vector>

namespace ray {

// `ray view ARGS...`: args are those after "view".
int runViewModule(const std::vector<std::string>& args);

// The render command on this rank of an mpirun launch, with main()'s argc and argv.
int runMpiModule(int argc, char** argv);

}  // namespace ray
