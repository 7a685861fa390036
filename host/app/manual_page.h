// ray(1): the manual page in roff, written from the commands' references
// (app/command_reference.h): the render command's description, options, render settings
// and exit status, then each subcommand with its own. Built at build time
// (host/main/reference_main.cpp), installed as man1/ray.1.gz.
#pragma once

#include <string>
#include <vector>

#include "app/command_reference.h"

namespace ray {

// `commands`: the render command first, then the subcommands.
std::string manualPage(const std::vector<CommandReference>& commands, const std::string& version);

// Text for roff: backslashes and leading dots escaped, option dashes as \- (so that a
// copied option is typed with ASCII hyphens).
std::string roffText(const std::string& text);

}  // namespace ray
