// Seconds on the steady clock, for timings and deadlines (never the wall clock, which jumps).
#pragma once

#include <chrono>

namespace ray {

inline double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace ray
