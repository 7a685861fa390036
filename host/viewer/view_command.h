// `ray view scene.xml [--port N] [--bind ADDRESS] [w h] [depth]`: the live viewer.
#pragma once

#include <string>
#include <vector>

namespace ray {

// args: everything after "view". Returns the exit status (2 for bad input, 3 when the
// server cannot start).
int runViewCommand(const std::vector<std::string>& args);

}  // namespace ray
