// ray_reference: writes ray(1) and the bash and zsh completions from ray's command line
// (app/command_reference.h), at build time (cmake/reference.cmake):
//   ray_reference man|bash|zsh OUTPUT
// Fails (exit 1, naming the option) when a command's parser and its --help disagree.
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "app/command_reference.h"
#include "app/convert_command.h"
#include "app/manual_page.h"
#include "app/shell_completion.h"
#include "core/atomic_file.h"
#include "explain/explain_command.h"
#include "viewer/view_command.h"

namespace {

// The render command, then the subcommands in the order `ray --help` lists them
// (host/main/main.cpp's kSubcommands; tests/reference_pages.py checks that the two agree).
std::vector<ray::CommandReference> rayCommands() {
    return {ray::renderCommandReference(), ray::viewCommandReference(), ray::explainCommandReference(),
            ray::convertCommandReference()};
}

}  // namespace

int main(int argc, char** argv) {
    const std::vector<std::string> args(argv + 1, argv + argc);
    if (args.size() != 2 || (args[0] != "man" && args[0] != "bash" && args[0] != "zsh")) {
        std::cerr << "usage: ray_reference man|bash|zsh OUTPUT\n";
        return 2;
    }
    try {
        const std::vector<ray::CommandReference> commands = rayCommands();
        const std::string text = args[0] == "man"    ? ray::manualPage(commands, RAY_VERSION)
                                 : args[0] == "bash" ? ray::bashCompletion(commands)
                                                     : ray::zshCompletion(commands);
        ray::writeFileAtomically(args[1], text);
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "ray_reference: " << e.what() << "\n";
        return 1;
    }
}
