// The error of a bad command line, shared by every command (ray, ray view, ray explain and
// the MPI render), each of which catches it and prints its message with the usage.
#pragma once

#include <stdexcept>

namespace ray {

// Thrown for bad arguments; the message says what is wrong and what to do.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace ray
