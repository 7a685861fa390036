// `ray view scene.xml [--port N] [--bind ADDRESS] [--no-token] [--width W --height H] [--depth D]
// [--aa course|off] [--device D]`: the live viewer (`ray view --help`).
#pragma once

#include <string>
#include <vector>

#include "app/command_reference.h"

namespace ray {

// Its parser and --help, for the manual page and the shell completions.
CommandReference viewCommandReference();

// args: everything after "view". Returns the exit status (2 for bad input, 3 when the
// server cannot start).
int runViewCommand(const std::vector<std::string>& args);

}  // namespace ray
