// What text an XML 1.0 file can hold (xml_characters.h).
#include "scene/xml_characters.h"

#include <cstdio>

namespace ray {

std::optional<Utf8Character> decodeUtf8(std::string_view text, size_t at) {
    const auto byte = [&](size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char lead = byte(at);
    if (lead < 0x80) return Utf8Character{lead, 1};
    size_t length = 0;
    char32_t code = 0, least = 0;
    if (lead >= 0xC2 && lead <= 0xDF) length = 2, code = lead & 0x1F, least = 0x80;
    else if (lead >= 0xE0 && lead <= 0xEF) length = 3, code = lead & 0x0F, least = 0x800;
    else if (lead >= 0xF0 && lead <= 0xF4) length = 4, code = lead & 0x07, least = 0x10000;
    else return std::nullopt;  // a continuation byte, or a lead byte UTF-8 never uses
    if (text.size() - at < length) return std::nullopt;
    for (size_t i = 1; i < length; ++i) {
        if ((byte(at + i) & 0xC0) != 0x80) return std::nullopt;
        code = (code << 6) | (byte(at + i) & 0x3F);
    }
    if (code < least || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return std::nullopt;
    return Utf8Character{code, length};
}

std::optional<UnwritableCharacter> firstUnwritableCharacter(std::string_view text) {
    size_t character = 1;
    for (size_t at = 0; at < text.size(); ++character) {
        const std::optional<Utf8Character> c = decodeUtf8(text, at);
        char what[40];
        if (!c) {
            std::snprintf(what, sizeof what, "byte 0x%02X (not UTF-8)", static_cast<unsigned char>(text[at]));
            return UnwritableCharacter{character, what};
        }
        if (!isXmlCharacter(c->code)) {
            std::snprintf(what, sizeof what, "U+%04X", unsigned(c->code));
            return UnwritableCharacter{character, what};
        }
        at += c->bytes;
    }
    return std::nullopt;
}

std::string unwritableSentence(std::string_view field, const UnwritableCharacter& found) {
    return std::string(field) + ": " + found.what + " at character " + std::to_string(found.character) +
           " cannot be written in an XML file";
}

std::string shownAsUtf8(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (size_t at = 0; at < text.size();) {
        const std::optional<Utf8Character> c = decodeUtf8(text, at);
        if (c) out.append(text.substr(at, c->bytes));
        else out += "\xEF\xBF\xBD";
        at += c ? c->bytes : 1;
    }
    return out;
}

size_t characterCount(std::string_view text) {
    size_t count = 0;
    for (size_t at = 0; at < text.size(); ++count) {
        const std::optional<Utf8Character> c = decodeUtf8(text, at);
        at += c ? c->bytes : 1;
    }
    return count;
}

std::string_view firstCharacters(std::string_view text, size_t characters) {
    size_t at = 0;
    for (size_t count = 0; count < characters && at < text.size(); ++count) {
        const std::optional<Utf8Character> c = decodeUtf8(text, at);
        at += c ? c->bytes : 1;
    }
    return text.substr(0, at);
}

}  // namespace ray
