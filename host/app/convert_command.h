// `ray convert IN OUT`: a scene from the CS123 XML format into the course's JSON (CS1230,
// SPEC §7) or back, the format of OUT by its name (.json or .xml), that of IN by its text
// as the loader reads it. Writes OUT through the one writer (core/atomic_file.h) once the
// text is known to load back as the same scene; on any bad input, nothing is written.
#pragma once

#include <string>
#include <vector>

#include "app/command_reference.h"

namespace ray {

// Its parser and --help, for the manual page and the shell completions.
CommandReference convertCommandReference();

// args: everything after "convert". Returns the exit status (0; 2 for bad input or
// arguments, OUT refused; 3 when OUT could not be written).
int runConvertCommand(const std::vector<std::string>& args);

}  // namespace ray
