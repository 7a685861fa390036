// What text an XML 1.0 file can hold (its Char production), counted and cut as characters.
//
// A scene file is XML: every name, path and text a save writes must be characters XML 1.0
// allows (tab, line feed, carriage return, U+0020 to U+D7FF, U+E000 to U+FFFD, U+10000 to
// U+10FFFF), given as valid UTF-8. A file holding U+FFFE, U+FFFF, another C0 control or a
// surrogate, even as a character reference, is one no XML parser reads, ray's included:
// the edits refuse such text before anything changes (edit/field_values.cpp), and the
// writers check what they write (canonical_writer.h). Lengths are counted, and long text
// cut, in characters, never through the bytes of one.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace ray {

// The first thing in `text` that XML cannot hold: a character outside Char, or bytes that
// are not UTF-8.
struct UnwritableCharacter {
    size_t character = 0;  // 1-based: the character it is (or, for bytes, the one it would be)
    std::string what;      // "U+FFFF", or "byte 0xC3 (not UTF-8)"
};
std::optional<UnwritableCharacter> firstUnwritableCharacter(std::string_view text);

// "name: U+FFFF at character 4 cannot be written in an XML file": the sentence the edits
// and the writers refuse such text with, naming the field (or what the text is).
std::string unwritableSentence(std::string_view field, const UnwritableCharacter& found);

// Whether XML 1.0 allows the code point (its Char production).
constexpr bool isXmlCharacter(char32_t c) {
    return c == 0x9 || c == 0xA || c == 0xD || (c >= 0x20 && c <= 0xD7FF) || (c >= 0xE000 && c <= 0xFFFD) ||
           (c >= 0x10000 && c <= 0x10FFFF);
}

// The code point of the UTF-8 sequence at `text[at]`, and its length in bytes; nullopt
// for bytes that are not UTF-8 (a stray continuation byte, a sequence cut short, an
// overlong form, a surrogate, a code point past U+10FFFF).
struct Utf8Character {
    char32_t code = 0;
    size_t bytes = 0;
};
std::optional<Utf8Character> decodeUtf8(std::string_view text, size_t at);

// `text` for a message: each byte that is not UTF-8 shown as U+FFFD (a message is UTF-8:
// the viewer sends it as JSON).
std::string shownAsUtf8(std::string_view text);

// The characters in `text` (a byte that is not UTF-8 counts as one).
size_t characterCount(std::string_view text);
// The longest start of `text` of at most `characters` characters: a cut between two.
std::string_view firstCharacters(std::string_view text, size_t characters);

}  // namespace ray
