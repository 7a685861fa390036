#include "app/command_reference.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "app/cli.h"
#include "render/settings_table.h"

namespace ray {

namespace {

std::string trimmed(const std::string& text) {
    const size_t first = text.find_first_not_of(' ');
    if (first == std::string::npos) return "";
    return text.substr(first, text.find_last_not_of(' ') - first + 1);
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

// "  -o, --output FILE        output image; ...": an entry starts two spaces in with a dash.
bool startsEntry(const std::string& line) { return line.rfind("  -", 0) == 0; }

// A heading on a line of its own ("options:", "render settings (...):"), or the start of a
// paragraph that names its section ("exit status: 0 success, ...").
bool splitHeading(const std::string& line, std::string& title, std::string& rest) {
    if (line.empty() || line[0] == ' ') return false;
    if (line.back() == ':') {
        title = line.substr(0, line.size() - 1);
        rest.clear();
        return true;
    }
    const size_t colon = line.find(": ");
    if (colon == std::string::npos || colon == 0) return false;
    const std::string head = line.substr(0, colon);
    if (!std::all_of(head.begin(), head.end(), [](char c) { return (c >= 'a' && c <= 'z') || c == ' '; }))
        return false;
    title = head;
    rest = line.substr(colon + 2);
    return true;
}

void appendText(std::string& text, const std::string& more) {
    if (more.empty()) return;
    text += (text.empty() ? "" : " ") + more;
}

// A new entry from its first line: the term up to the gap before the text.
HelpItem entryFrom(const std::string& line) {
    const size_t gap = line.find("  ", 2);
    if (gap == std::string::npos) return {trimmed(line), ""};
    return {trimmed(line.substr(0, gap)), trimmed(line.substr(gap))};
}

// The phrase zsh shows beside an option: its text up to the first ';' or '(' (at most 70
// characters, cut at a word).
std::string firstPhrase(const std::string& text) {
    std::string phrase = text.substr(0, text.find_first_of(";("));
    if (phrase.size() > 70) phrase = phrase.substr(0, phrase.rfind(' ', 70));
    return trimmed(phrase);
}

// The --help entry that lists `name`, or null.
const HelpItem* entryNaming(const std::vector<HelpSection>& sections, const std::string& name) {
    for (const HelpSection& section : sections)
        for (const HelpItem& item : section.items) {
            const std::vector<std::string> names = item.optionNames();
            if (std::find(names.begin(), names.end(), name) != names.end()) return &item;
        }
    return nullptr;
}

// The value's name after `name` in the entry's term ("FILE" of "-o, --output FILE").
std::string valueNameIn(const HelpItem& entry, const std::string& name) {
    std::istringstream words(entry.term);
    for (std::string word; words >> word;) {
        if (!word.empty() && word.back() == ',') word.pop_back();
        if (word == name) {
            std::string value;
            words >> value;
            if (!value.empty() && value.back() == ',') value.pop_back();
            return value.empty() || value[0] == '-' ? "" : value;
        }
    }
    return "";
}

std::vector<std::string> parserNames(const CLI::Option& option) {
    std::vector<std::string> names;
    for (const std::string& name : option.get_snames()) names.push_back("-" + name);
    for (const std::string& name : option.get_lnames()) names.push_back("--" + name);
    return names;
}

void completeValue(OptionReference& option, const std::string& valueName) {
    for (const SettingSpec& spec : renderSettingsTable()) {
        if (spec.positional || spec.optionName() != option.names.back() || spec.kind() != SettingKind::Choice) continue;
        option.completion = ValueCompletion::Choice;
        for (const SettingChoice& choice : spec.choices) option.choices.emplace_back(choice.name);
        return;
    }
    if (option.names.back() == "--device") option.completion = ValueCompletion::Device;
    else if (valueName == "FILE") option.completion = ValueCompletion::File;
    else if (valueName == "DIR") option.completion = ValueCompletion::Folder;
}

std::string commandName(const std::string& subcommand) { return subcommand.empty() ? "ray" : "ray " + subcommand; }

}  // namespace

std::vector<std::string> HelpItem::optionNames() const {
    std::vector<std::string> names;
    std::istringstream pieces(term);
    for (std::string word; pieces >> word;) {
        if (!word.empty() && word.back() == ',') word.pop_back();
        if (word.size() > 1 && word[0] == '-') names.push_back(word);
    }
    return names;
}

std::vector<HelpSection> parseHelpText(const std::string& usage, std::string& synopsis) {
    const std::vector<std::string> text = lines(usage);
    const std::string prefix = "usage: ";
    if (text.empty() || text[0].rfind(prefix, 0) != 0)
        throw std::runtime_error("a command's --help must begin with 'usage: ', not '" +
                                 (text.empty() ? std::string() : text[0]) + "'");
    synopsis = text[0].substr(prefix.size());
    std::vector<HelpSection> sections(1);
    HelpItem* current = nullptr;  // the paragraph or entry being read; null after a blank line
    for (size_t i = 1; i < text.size(); ++i) {
        const std::string& line = text[i];
        std::string title, rest;
        if (trimmed(line).empty()) {
            current = nullptr;
        } else if (startsEntry(line)) {
            sections.back().items.push_back(entryFrom(line));
            current = &sections.back().items.back();
        } else if (line[0] == ' ' && current) {
            appendText(current->text, trimmed(line));
        } else if (!current && splitHeading(line, title, rest)) {
            sections.push_back({title, {}});
            if (!rest.empty()) {
                sections.back().items.push_back({"", rest});
                current = &sections.back().items.back();
            }
        } else if (current && current->term.empty()) {
            appendText(current->text, trimmed(line));
        } else {
            sections.back().items.push_back({"", trimmed(line)});
            current = &sections.back().items.back();
        }
    }
    return sections;
}

CommandReference describeCommand(const std::string& subcommand, const CLI::App& app, const std::string& usage) {
    CommandReference reference;
    reference.subcommand = subcommand;
    reference.sections = parseHelpText(usage, reference.synopsis);
    const std::string command = commandName(subcommand);
    std::vector<std::string> taken;
    for (const CLI::Option* option : app.get_options()) {
        std::vector<std::string> names = parserNames(*option);
        if (names.empty()) continue;  // a positional
        const HelpItem* entry = entryNaming(reference.sections, names.back());
        if (!entry)
            throw std::runtime_error("`" + command + " --help` has no entry for " + names.back() +
                                     ", which its parser takes: add one (the manual page and the shell "
                                     "completions are made from it)");
        OptionReference described;
        described.names = names;
        described.takesValue = option->get_expected_max() != 0;
        if (described.takesValue) completeValue(described, valueNameIn(*entry, names.back()));
        described.summary = firstPhrase(entry->text);
        taken.insert(taken.end(), names.begin(), names.end());
        reference.options.push_back(std::move(described));
    }
    for (const HelpSection& section : reference.sections)
        for (const HelpItem& item : section.items)
            for (const std::string& name : item.optionNames())
                if (std::find(taken.begin(), taken.end(), name) == taken.end())
                    throw std::runtime_error("`" + command + " --help` lists " + name + ", which its parser does not take");
    return reference;
}

CommandReference renderCommandReference() {
    CLI::App app("ray", "ray");
    CliOptions options;
    std::vector<std::string> positionals;
    defineRenderCommand(app, options, positionals);
    return describeCommand("", app, kUsageText);
}

}  // namespace ray
