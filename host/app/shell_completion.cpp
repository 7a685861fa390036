#include "app/shell_completion.h"

#include <algorithm>

namespace ray {

namespace {

std::string joined(const std::vector<std::string>& words, const std::string& separator) {
    std::string out;
    for (const std::string& word : words) out += (out.empty() ? "" : separator) + word;
    return out;
}

std::string commandKey(const CommandReference& command) {
    return command.subcommand.empty() ? "render" : command.subcommand;
}

std::vector<std::string> subcommandNames(const std::vector<CommandReference>& commands) {
    std::vector<std::string> names;
    for (size_t i = 1; i < commands.size(); ++i) names.push_back(commands[i].subcommand);
    return names;
}

// What a command's description says first, for zsh's menu of subcommands.
std::string commandSummary(const CommandReference& command) {
    const std::vector<HelpItem>& items = command.sections.front().items;
    const std::string text = items.empty() ? command.synopsis : items.front().text;
    std::string summary = text.substr(0, text.find_first_of(":.;"));
    if (summary.size() > 70) summary = summary.substr(0, summary.rfind(' ', 70));
    return summary;
}

// ---------------------------------------------------------------------------------------
// bash

const char* const kBashHelpers = R"(# bash completion for ray(1), generated from ray's command line by ray_reference: do not edit.

# What --device takes: the words, then the indices that `ray --list-devices` prints now.
_ray_devices() {
    local listed
    listed=$("${1:-ray}" --list-devices 2>/dev/null | sed -n 's/^\([0-9][0-9]*\): .*/\1/p')
    echo auto cpu gpu all ref $listed
}

# File names, one a line (names with spaces stay whole).
_ray_files() {
    local IFS=$'\n'
    compopt -o filenames 2>/dev/null
    COMPREPLY+=($(compgen -f -- "$cur"))
}
_ray_folders() {
    local IFS=$'\n'
    compopt -o filenames 2>/dev/null
    COMPREPLY+=($(compgen -d -- "$cur"))
}
# The scene files ray reads, and the folders on the way to them.
_ray_scenes() {
    local IFS=$'\n' extension
    compopt -o filenames 2>/dev/null
    COMPREPLY+=($(compgen -d -- "$cur"))
    for extension in xml json ini; do
        COMPREPLY+=($(compgen -f -X "!*.$extension" -- "$cur"))
    done
}
)";

// `case` arms for the values of a command's options.
std::string bashValueArms(const CommandReference& command) {
    std::string arms;
    for (const OptionReference& option : command.options) {
        if (!option.takesValue) continue;
        std::vector<std::string> patterns;
        for (const std::string& name : option.names) {
            std::string pattern = "\"";  // appended, not added: GCC 12 warns (-Wrestrict) on "..." + std::string&&
            pattern.append(commandKey(command)).append(" ").append(name).append("\"");
            patterns.push_back(pattern);
        }
        std::string action;
        switch (option.completion) {
            case ValueCompletion::Choice:
                action = "COMPREPLY=($(compgen -W \"" + joined(option.choices, " ") + "\" -- \"$cur\"))";
                break;
            case ValueCompletion::File: action = "_ray_files"; break;
            case ValueCompletion::Folder: action = "_ray_folders"; break;
            case ValueCompletion::Device:
                action = "COMPREPLY=($(compgen -W \"$(_ray_devices \"${COMP_WORDS[0]}\")\" -- \"$cur\"))";
                break;
            case ValueCompletion::None: action = ":"; break;  // a number or an address
        }
        arms += "            " + joined(patterns, "|") + ") " + action + " ;;\n";
    }
    return arms;
}

}  // namespace

std::string bashCompletion(const std::vector<CommandReference>& commands) {
    std::string script = kBashHelpers;
    script += "\n_ray() {\n"
              "    local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]}\n"
              "    local command=render first=1 options valued\n"
              "    COMPREPLY=()\n"
              "    case ${COMP_WORDS[1]} in\n"
              "        " + joined(subcommandNames(commands), "|") +
              ") if (( COMP_CWORD > 1 )); then command=${COMP_WORDS[1]}; first=2; fi ;;\n"
              "    esac\n"
              "    # Each command's options, and those of them that take a value.\n"
              "    case $command in\n";
    for (const CommandReference& command : commands) {
        std::vector<std::string> all, valued;
        for (const OptionReference& option : command.options)
            for (const std::string& name : option.names) {
                all.push_back(name);
                if (option.takesValue) valued.push_back(name);
            }
        script += "        " + commandKey(command) + ") options=\"" + joined(all, " ") + "\"; valued=\" " +
                  joined(valued, " ") + " \" ;;\n";
    }
    script += "    esac\n"
              "    # The value of the option before the cursor.\n"
              "    if [[ $valued == *\" $prev \"* ]]; then\n"
              "        case \"$command $prev\" in\n";
    for (const CommandReference& command : commands) script += bashValueArms(command);
    script += "        esac\n"
              "        return 0\n"
              "    fi\n"
              "    if [[ $cur == -* ]]; then\n"
              "        COMPREPLY=($(compgen -W \"$options\" -- \"$cur\"))\n"
              "        return 0\n"
              "    fi\n"
              "    # The first word that is neither an option nor an option's value is the scene.\n"
              "    local i positionals=0\n"
              "    for (( i = first; i < COMP_CWORD; i++ )); do\n"
              "        if [[ ${COMP_WORDS[i]} == -* ]]; then\n"
              "            [[ $valued == *\" ${COMP_WORDS[i]} \"* ]] && i=$((i + 1))\n"
              "        else\n"
              "            positionals=$((positionals + 1))\n"
              "        fi\n"
              "    done\n"
              "    if (( positionals == 0 )); then\n"
              "        _ray_scenes\n"
              "        if (( COMP_CWORD == 1 )); then COMPREPLY+=($(compgen -W \"" +
              joined(subcommandNames(commands), " ") + "\" -- \"$cur\")); fi\n"
              "    fi\n"
              "    return 0\n"
              "}\n"
              "complete -F _ray ray\n";
    return script;
}

// ---------------------------------------------------------------------------------------
// zsh

namespace {

// A description inside a single-quoted _arguments spec: none of the characters that end or
// structure it.
std::string zshDescription(const std::string& text) {
    std::string out;
    for (char c : text)
        if (std::string("'\"\\`$[]():").find(c) == std::string::npos) out += c;
    return out;
}

std::string zshOptionSpec(const OptionReference& option) {
    std::string spec;
    std::string description = "[";  // appended, not added: GCC 12 warns (-Wrestrict) on "..." + std::string&&
    description.append(zshDescription(option.summary)).append("]");
    if (option.names.size() > 1)
        spec.append("'(").append(joined(option.names, " ")).append(")'{").append(joined(option.names, ",")).append("}'").append(description);
    else
        spec = "'" + option.names.front() + description;
    if (option.takesValue) {
        switch (option.completion) {
            case ValueCompletion::Choice: spec += ":value:(" + joined(option.choices, " ") + ")"; break;
            case ValueCompletion::File: spec += ":file:_files"; break;
            case ValueCompletion::Folder: spec += ":folder:_files -/"; break;
            case ValueCompletion::Device: spec += ":device:_ray_devices"; break;
            case ValueCompletion::None: spec += ":value: "; break;
        }
    }
    return spec + "'";
}

}  // namespace

std::string zshCompletion(const std::vector<CommandReference>& commands) {
    std::string script =
        "#compdef ray\n"
        "# zsh completion for ray(1), generated from ray's command line by ray_reference: do not edit.\n\n"
        "# What --device takes: the words, then the indices that `ray --list-devices` prints now.\n"
        "_ray_devices() {\n"
        "  local -a devices\n"
        "  devices=(auto cpu gpu all ref ${(f)\"$(ray --list-devices 2>/dev/null | sed -n 's/^\\([0-9][0-9]*\\): .*/\\1/p')\"})\n"
        "  compadd -a devices\n"
        "}\n"
        "# The scene files ray reads.\n"
        "_ray_scenes() { _files -g '*.(xml|json|ini)(-.)' }\n"
        "# The first argument: a subcommand or a scene file.\n"
        "_ray_first() {\n"
        "  local -a subcommands\n"
        "  subcommands=(\n";
    for (size_t i = 1; i < commands.size(); ++i)
        script += "    '" + commands[i].subcommand + ":" + zshDescription(commandSummary(commands[i])) + "'\n";
    script += "  )\n"
              "  _describe -t subcommands subcommand subcommands\n"
              "  _ray_scenes\n"
              "}\n";
    for (const CommandReference& command : commands) {
        script += "_ray_" + commandKey(command) + "() {\n  _arguments -s -S \\\n";
        for (const OptionReference& option : command.options) script += "    " + zshOptionSpec(option) + " \\\n";
        script += std::string("    '1:scene file:") + (command.subcommand.empty() ? "_ray_first" : "_ray_scenes") +
                  "' \\\n    '*:number: '\n}\n";
    }
    script += "_ray() {\n"
              "  if (( CURRENT > 2 )) && [[ $words[2] == (" + joined(subcommandNames(commands), "|") + ") ]]; then\n"
              "    local command=$words[2]\n"
              "    shift words\n"
              "    (( CURRENT-- ))\n"
              "    _ray_$command\n"
              "  else\n"
              "    _ray_render\n"
              "  fi\n"
              "}\n"
              "_ray \"$@\"\n";
    return script;
}

}  // namespace ray
