// Reading and writing a value's text (value_text.h).
#include "scene/value_text.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>

namespace ray {
namespace {

bool isBlank(const char* text) {
    for (; *text; ++text)
        if (!std::isspace(static_cast<unsigned char>(*text))) return false;
    return true;
}

// A plain decimal ("-3.65636", "0.1", "20": an optional '-', digits with an optional
// point, nothing else) of at most 19 digits, at most 22 of them after the point, whose
// digits make an integer w <= 2^53, is w / 10^k with both w and 10^k exact doubles: the one
// division, rounded correctly, gives exactly strtod's value (Clinger's fast path). Nullopt
// for anything else. A large flat scene has millions of numbers, and strtod was a tenth of
// its load.
std::optional<double> plainDecimal(const char* text) {
    static constexpr double kPowersOfTen[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                              1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                              1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const char* p = text;
    const bool negative = *p == '-';
    if (negative) ++p;
    uint64_t digits = 0;
    int count = 0, afterPoint = -1;  // -1: no point yet
    for (;; ++p) {
        if (*p >= '0' && *p <= '9') {
            if (++count > 19) return std::nullopt;
            digits = digits * 10 + uint64_t(*p - '0');
            if (afterPoint >= 0) ++afterPoint;
        } else if (*p == '.' && afterPoint < 0) {
            afterPoint = 0;
        } else {
            break;
        }
    }
    if (*p != '\0' || count == 0 || digits > (uint64_t(1) << 53) || afterPoint > 22) return std::nullopt;
    const double value = double(digits) / kPowersOfTen[std::max(afterPoint, 0)];
    return negative ? -value : value;
}

// The value `text` holds when it is a whole decimal number (surrounding blanks allowed).
std::optional<double> parseNumber(const char* text) {
    if (std::optional<double> value = plainDecimal(text)) return value;
    char* end = nullptr;
    double value = std::strtod(text, &end);
    if (end == text) return std::nullopt;
    while (std::isspace(static_cast<unsigned char>(*end))) ++end;
    if (*end != '\0') return std::nullopt;
    return value;
}

NumberReading reading(std::optional<double> value, NumberReading::Kind kind) {
    if (!value) return {NumberReading::Kind::NotANumber, 0};
    if (!std::isfinite(*value)) return {NumberReading::Kind::NotFinite, *value};
    return {kind, *value};
}

}  // namespace

NumberReading readNumber(const char* text) {
    // The common case first.
    if (std::optional<double> value = parseNumber(text); value && std::isfinite(*value))
        return {NumberReading::Kind::Number, *value};
    if (isBlank(text)) return {NumberReading::Kind::Blank, 0};
    if (text[0] == '=')
        if (std::optional<double> value = parseNumber(text + 1))
            return reading(value, NumberReading::Kind::StrayEquals);
    return reading(parseNumber(text), NumberReading::Kind::Number);
}

std::string shortestNumber(double value) {
    char buffer[64];
    auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
    return ec == std::errc() ? std::string(buffer, end) : std::to_string(value);
}

}  // namespace ray
