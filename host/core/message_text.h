// Text from outside (a file name, a field's name, a value) as a message may quote it: a
// message is read by a person, so a name of 100,000 characters is cut to its two ends, and
// control characters (a NUL, a newline that would forge a second line of a log) are shown
// escaped rather than written.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace ray {

// The longest quote a message holds, in bytes: longer text keeps its first and last
// characters with "…" between (a path's folder and its file name both show).
constexpr size_t kMaxQuotedLength = 200;

// `text` with control characters written as \n, \t, \r or \xNN, cut as above; UTF-8
// characters are never split.
std::string quotedForMessage(std::string_view text, size_t maxLength = kMaxQuotedLength);

}  // namespace ray
