// `ray explain scene.xml X Y [w h] [depth] [options]`: prints the tree of rays of pixel
// (X, Y) as the reference renderer traces it, and with --json FILE writes it as JSON.
#pragma once

#include <string>
#include <vector>

#include "app/command_reference.h"

namespace ray {

// Its parser and --help, for the manual page and the shell completions.
CommandReference explainCommandReference();

// args: everything after "explain". Returns the exit status (0, 2 for bad input).
int runExplainCommand(const std::vector<std::string>& args);

}  // namespace ray
