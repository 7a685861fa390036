// `ray view scene.xml [--port N] [--bind ADDRESS] [--no-token] [--width W --height H] [--depth D]
// [--aa course|off] [--device D]`: the live viewer (`ray view --help`).
#pragma once

#include <string>
#include <vector>

namespace ray {

// args: everything after "view". Returns the exit status (2 for bad input, 3 when the
// server cannot start).
int runViewCommand(const std::vector<std::string>& args);

}  // namespace ray
