// Completion of ray's command line in bash and zsh, written from the commands' references
// (app/command_reference.h) at build time (host/main/reference_main.cpp): the subcommands,
// each command's options, their values (a setting's choices, files, folders, the devices
// `ray --list-devices` lists when the completion runs) and scene files (.xml, .json, .ini)
// for the first argument. Installed as share/bash-completion/completions/ray and
// share/zsh/vendor-completions/_ray.
#pragma once

#include <string>
#include <vector>

#include "app/command_reference.h"

namespace ray {

// `commands`: the render command first, then the subcommands.
std::string bashCompletion(const std::vector<CommandReference>& commands);
std::string zshCompletion(const std::vector<CommandReference>& commands);

}  // namespace ray
