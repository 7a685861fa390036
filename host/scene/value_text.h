// How the scene format reads and writes a value's text (SPEC §1): names and keywords
// matched ignoring case, numbers read leniently as the loader reads them, and written back
// in the shortest form that reads as the same double. The loader (scene_loader_parse.cpp)
// and the saver (document_splices.cpp, which compares a document with its file's text)
// share these, so that a number the file holds is never rewritten as an edit.
#pragma once

#include <optional>
#include <string>

namespace ray {

constexpr char asciiLower(char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; }

// Names and keywords match ignoring case, ASCII only as strcasecmp in the C locale does.
// Inline: a large flat scene compares millions of names, and the calls to strcasecmp were a
// sixth of its parse.
inline bool sameName(const char* a, const char* b) {
    if (!a || !b) return false;
    for (;; ++a, ++b) {
        const char x = asciiLower(*a);
        if (x != asciiLower(*b)) return false;
        if (x == '\0') return true;
    }
}

// An attribute's text read as a number, and how it read: the loader takes a plain number
// as it is, a blank as 0 and a stray '=' before a number ("r="=0.1"", as in the course's
// pikachu_head.xml) as the number, each of the last two with a warning; the rest is an error.
struct NumberReading {
    enum class Kind { Number, Blank, StrayEquals, NotANumber, NotFinite };
    Kind kind = Kind::NotANumber;
    double value = 0;  // what the loader takes (0 for NotANumber)

    bool loads() const { return kind == Kind::Number || kind == Kind::Blank || kind == Kind::StrayEquals; }
};
NumberReading readNumber(const char* text);

// The shortest text that reads back as the same double (std::to_chars), so that a saved
// scene loads to the same bits.
std::string shortestNumber(double value);

}  // namespace ray
