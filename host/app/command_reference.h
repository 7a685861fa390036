// What the manual page, ray(1), and the shell completions say of a command, read off the two
// things the command is made of: its CLI11 parser (the option names it takes and whether
// each takes a value) and its --help text (what each option is for, the sections, the exit
// status), whose render settings come from the settings table (render/settings_table.h).
// Both are checked against each other here: an option the parser takes without an entry in
// --help, or an entry for an option it does not take, is an error, so that the build of the
// manual page fails rather than leaving an option out. What a value completes to comes from
// the settings table (a choice's names) and from the value's name in --help (FILE, DIR).
//
// The writers: app/manual_page.h, app/shell_completion.h; the program that runs them at
// build time: host/main/reference_main.cpp.
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace ray {

// What an option's value completes to in the shell.
enum class ValueCompletion {
    None,    // a number, an address: nothing to offer
    Choice,  // one of `choices`
    File,    // a file name (FILE)
    Folder,  // a folder (DIR)
    Device,  // auto, cpu, gpu, all, ref and the indices `ray --list-devices` prints
};

struct OptionReference {
    std::vector<std::string> names;  // "-o", "--output"
    bool takesValue = false;
    ValueCompletion completion = ValueCompletion::None;
    std::vector<std::string> choices;  // Choice: "off", "course", ...
    std::string summary;               // its --help text's first phrase, for zsh's menu
};

// A paragraph of --help: an option's entry ("-o, --output FILE" and its text) or, with an
// empty term, prose.
struct HelpItem {
    std::string term;
    std::string text;  // its lines joined with single spaces
    // The option names the term lists: "--width N, --height N" gives --width, --height.
    std::vector<std::string> optionNames() const;
};

// A part of --help under its heading ("options", "exit status"); the first, untitled, is
// the description after the usage line.
struct HelpSection {
    std::string title;
    std::vector<HelpItem> items;
};

struct CommandReference {
    std::string subcommand;  // "" for the render command; "view", "explain"
    std::string synopsis;    // the usage line after "usage: "
    std::vector<HelpSection> sections;
    std::vector<OptionReference> options;  // in the parser's order
};

// --help's text in sections. Throws std::runtime_error when it does not begin with "usage: ".
std::vector<HelpSection> parseHelpText(const std::string& usage, std::string& synopsis);

// The command's reference from its parser and its --help text. Throws std::runtime_error
// naming an option of the parser that --help has no entry for, or the reverse.
CommandReference describeCommand(const std::string& subcommand, const CLI::App& app, const std::string& usage);

// The render command's (`ray <scene.xml> ...`): defineRenderCommand and kUsageText.
CommandReference renderCommandReference();

}  // namespace ray
