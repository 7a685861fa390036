#include "core/message_text.h"

namespace ray {

namespace {

bool isContinuationByte(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

// The control characters of `text` escaped; the rest as it is.
std::string escaped(std::string_view text) {
    static const char* const kHex = "0123456789abcdef";
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (c == '\n') out += "\\n";
        else if (c == '\t') out += "\\t";
        else if (c == '\r') out += "\\r";
        else if (byte < 0x20 || byte == 0x7f) out += std::string("\\x") + kHex[byte >> 4] + kHex[byte & 15];
        else out += c;
    }
    return out;
}

}  // namespace

std::string quotedForMessage(std::string_view text, size_t maxLength) {
    std::string out = escaped(text);
    if (out.size() <= maxLength) return out;
    const std::string marker = "…";
    size_t head = (maxLength - marker.size()) / 2, tail = out.size() - (maxLength - marker.size() - head);
    while (head > 0 && isContinuationByte(out[head])) --head;
    while (tail < out.size() && isContinuationByte(out[tail])) ++tail;
    return out.substr(0, head) + marker + out.substr(tail);
}

}  // namespace ray
