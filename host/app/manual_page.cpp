#include "app/manual_page.h"

#include <algorithm>
#include <cctype>

namespace ray {

namespace {

std::string uppercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::toupper(c)); });
    return text;
}

// "-o, --output FILE" as roff: names bold, values italic.
std::string roffTerm(const std::string& term) {
    std::string out;
    size_t at = 0;
    while (at < term.size()) {
        const size_t end = std::min(term.find_first_of(" ,", at), term.size());
        const std::string word = term.substr(at, end - at);
        if (!word.empty()) out += (word[0] == '-' ? "\\fB" : "\\fI") + roffText(word) + "\\fR";
        if (end < term.size()) out += term[end];
        at = end + 1;
    }
    return out;
}

void writeItems(std::string& page, const std::vector<HelpItem>& items) {
    for (const HelpItem& item : items) {
        if (item.term.empty()) page += ".PP\n" + roffText(item.text) + "\n";
        else page += ".TP\n" + roffTerm(item.term) + "\n" + roffText(item.text) + "\n";
    }
}

// A section heading: "render settings (ray, ray explain and ray view take the same)" as
// RENDER SETTINGS, its parenthesis a paragraph of its own.
void writeHeading(std::string& page, const std::string& title, const char* macro) {
    const size_t paren = title.find(" (");
    page += std::string(macro) + " " + roffText(uppercase(title.substr(0, paren))) + "\n";
    if (paren != std::string::npos) page += ".PP\n" + roffText(title.substr(paren + 1)) + "\n";
}

bool sameItems(const std::vector<HelpItem>& a, const std::vector<HelpItem>& b) {
    return a.size() == b.size() &&
           std::equal(a.begin(), a.end(), b.begin(), [](const HelpItem& x, const HelpItem& y) {
               return x.term == y.term && x.text == y.text;
           });
}

// A subcommand's part: its synopsis, description and sections; a section the render command
// already showed word for word (the render settings) is named, not repeated.
void writeSubcommand(std::string& page, const CommandReference& command, const CommandReference& render) {
    page += ".SS \"ray " + command.subcommand + "\"\n.PP\n\\fBray " + roffText(command.subcommand) + "\\fR" +
            roffText(command.synopsis.substr(command.synopsis.find(command.subcommand) + command.subcommand.size())) +
            "\n";
    for (const HelpSection& section : command.sections) {
        if (!section.title.empty()) {
            const bool shown = std::any_of(render.sections.begin(), render.sections.end(), [&](const HelpSection& s) {
                return s.title == section.title && sameItems(s.items, section.items);
            });
            page += ".PP\n\\fI" + roffText(section.title) + ":\\fR" +
                    (shown ? " as for \\fBray\\fR, above.\n" : "\n");
            if (shown) continue;
        }
        writeItems(page, section.items);
    }
}

}  // namespace

std::string roffText(const std::string& text) {
    std::string out;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        const bool startsOption = c == '-' && i + 1 < text.size() && (text[i + 1] == '-' || std::isalpha((unsigned char)text[i + 1])) &&
                                  (i == 0 || std::string(" ([|,'`").find(text[i - 1]) != std::string::npos ||
                                   (text[i - 1] == '-' && (i < 2 || text[i - 2] == ' ')));
        if (c == '\\') out += "\\e";
        else if (startsOption) out += "\\-";
        else out += c;
    }
    // A line of text that starts with . or ' would be read as a request.
    if (!out.empty() && (out[0] == '.' || out[0] == '\'')) out = "\\&" + out;
    return out;
}

std::string manualPage(const std::vector<CommandReference>& commands, const std::string& version) {
    const CommandReference& render = commands.front();
    std::string page = ".\\\" ray(1), generated from ray's command line by ray_reference: do not edit.\n";
    page += ".TH RAY 1 \"\" \"ray " + roffText(version) + "\" \"User Commands\"\n";
    page += ".SH NAME\nray \\- a ray tracer for CS123 scenefiles: render, view and edit, explain a pixel\n";
    page += ".SH SYNOPSIS\n.nf\n";
    for (const CommandReference& command : commands) page += "\\fBray\\fR " + roffText(command.synopsis.substr(4)) + "\n";
    page += ".fi\n.SH DESCRIPTION\n";
    for (const HelpSection& section : render.sections) {
        if (!section.title.empty()) writeHeading(page, section.title, ".SH");
        writeItems(page, section.items);
    }
    if (commands.size() > 1) {
        page += ".SH COMMANDS\n";
        for (size_t i = 1; i < commands.size(); ++i) writeSubcommand(page, commands[i], render);
    }
    page += ".SH SEE ALSO\nThe user guide, docs/user-guide.md, and docs/embedding.md (the C++ library and the "
            "Python module \\fBcs123ray\\fR) in ray's sources.\n";
    return page;
}

}  // namespace ray
