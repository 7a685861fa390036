// A scene file's encoding, and its text to and from UTF-8 (text_encoding.h).
#include "scene/text_encoding.h"

#include <cstdio>
#include <optional>

#include "scene/value_text.h"
#include "scene/xml_characters.h"

namespace ray {
namespace {

bool sameAsciiName(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (asciiLower(a[i]) != asciiLower(b[i])) return false;
    return true;
}

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// The encoding="..." of an XML declaration at the start of `bytes`; empty when none.
std::string_view declaredEncoding(std::string_view bytes) {
    if (bytes.starts_with("\xEF\xBB\xBF")) bytes.remove_prefix(3);
    if (!bytes.starts_with("<?xml") || bytes.size() < 6 || !isBlank(bytes[5])) return {};
    const std::string_view declaration = bytes.substr(0, bytes.find("?>"));
    size_t at = declaration.find("encoding");
    if (at == std::string_view::npos) return {};
    at += 8;
    while (at < declaration.size() && (isBlank(declaration[at]) || declaration[at] == '=')) ++at;
    if (at >= declaration.size() || (declaration[at] != '"' && declaration[at] != '\'')) return {};
    const size_t end = declaration.find(declaration[at], at + 1);
    if (end == std::string_view::npos) return {};
    return declaration.substr(at + 1, end - at - 1);
}

void appendUtf8(std::string& out, char32_t c) {
    if (c < 0x80) {
        out += char(c);
    } else if (c < 0x800) {
        out += char(0xC0 | (c >> 6));
        out += char(0x80 | (c & 0x3F));
    } else if (c < 0x10000) {
        out += char(0xE0 | (c >> 12));
        out += char(0x80 | ((c >> 6) & 0x3F));
        out += char(0x80 | (c & 0x3F));
    } else {
        out += char(0xF0 | (c >> 18));
        out += char(0x80 | ((c >> 12) & 0x3F));
        out += char(0x80 | ((c >> 6) & 0x3F));
        out += char(0x80 | (c & 0x3F));
    }
}

void appendUtf16(std::string& out, char32_t c, bool bigEndian) {
    const auto unit = [&](unsigned u) {
        const char high = char(u >> 8), low = char(u & 0xFF);
        out += bigEndian ? high : low;
        out += bigEndian ? low : high;
    };
    if (c < 0x10000) {
        unit(unsigned(c));
    } else {
        c -= 0x10000;
        unit(0xD800 | unsigned(c >> 10));
        unit(0xDC00 | unsigned(c & 0x3FF));
    }
}

std::string utf16ToUtf8(std::string_view bytes, bool bigEndian) {
    const auto unit = [&](size_t at) -> unsigned {
        const auto a = static_cast<unsigned char>(bytes[at]), b = static_cast<unsigned char>(bytes[at + 1]);
        return bigEndian ? (a << 8 | b) : (b << 8 | a);
    };
    std::string out;
    out.reserve(bytes.size() / 2);
    size_t at = 0;
    for (; at + 1 < bytes.size(); at += 2) {
        const unsigned u = unit(at);
        if (u >= 0xD800 && u <= 0xDBFF && at + 3 < bytes.size()) {
            const unsigned low = unit(at + 2);
            if (low >= 0xDC00 && low <= 0xDFFF) {
                appendUtf8(out, 0x10000 + ((char32_t(u) - 0xD800) << 10) + (low - 0xDC00));
                at += 2;
                continue;
            }
        }
        appendUtf8(out, u >= 0xD800 && u <= 0xDFFF ? 0xFFFD : char32_t(u));
    }
    if (at < bytes.size()) appendUtf8(out, 0xFFFD);  // an odd byte at the end
    return out;
}

std::string characterReference(char32_t c) {
    char reference[16];
    std::snprintf(reference, sizeof reference, "&#x%X;", unsigned(c));
    return reference;
}

}  // namespace

TextEncoding encodingOf(std::string_view bytes) {
    if (bytes.starts_with("\xFE\xFF") || bytes.starts_with(std::string_view("\0<", 2))) return TextEncoding::Utf16BE;
    if (bytes.starts_with("\xFF\xFE") || bytes.starts_with(std::string_view("<\0", 2))) return TextEncoding::Utf16LE;
    const std::string_view declared = declaredEncoding(bytes);
    if (sameAsciiName(declared, "ISO-8859-1")) return TextEncoding::Latin1;
    if (sameAsciiName(declared, "US-ASCII")) return TextEncoding::Ascii;
    return TextEncoding::Utf8;
}

const char* encodingName(TextEncoding encoding) {
    switch (encoding) {
        case TextEncoding::Latin1: return "ISO-8859-1";
        case TextEncoding::Ascii: return "US-ASCII";
        case TextEncoding::Utf16LE: return "UTF-16LE";
        case TextEncoding::Utf16BE: return "UTF-16BE";
        case TextEncoding::Utf8: break;
    }
    return "UTF-8";
}

std::string toUtf8(std::string_view bytes, TextEncoding encoding) {
    switch (encoding) {
        case TextEncoding::Utf8: return std::string(bytes);
        case TextEncoding::Utf16LE:
        case TextEncoding::Utf16BE: return utf16ToUtf8(bytes, encoding == TextEncoding::Utf16BE);
        case TextEncoding::Latin1:
        case TextEncoding::Ascii: break;
    }
    std::string out;
    out.reserve(bytes.size() + bytes.size() / 8);
    for (char byte : bytes) {
        const auto c = static_cast<unsigned char>(byte);
        // A US-ASCII file's bytes past 0x7F (only after the root element) read as ISO-8859-1's.
        appendUtf8(out, c);
    }
    return out;
}

std::string fromUtf8(std::string_view text, TextEncoding encoding) {
    if (encoding == TextEncoding::Utf8) return std::string(text);
    const bool utf16 = encoding == TextEncoding::Utf16LE || encoding == TextEncoding::Utf16BE;
    const char32_t beyond = encoding == TextEncoding::Latin1 ? 0x100 : 0x80;
    std::string out;
    out.reserve(utf16 ? 2 * text.size() : text.size());
    for (size_t at = 0; at < text.size();) {
        const std::optional<Utf8Character> c = decodeUtf8(text, at);
        const char32_t code = c ? c->code : 0xFFFD;  // never met: the writers check what they write
        at += c ? c->bytes : 1;
        if (utf16) appendUtf16(out, code, encoding == TextEncoding::Utf16BE);
        else if (code < beyond) out += char(code);
        else out += characterReference(code);
    }
    return out;
}

}  // namespace ray
