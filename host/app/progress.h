// A progress bar on stderr, shown only when stderr is a terminal.
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>

namespace ray {

class ProgressBar {
public:
    explicit ProgressBar(bool enabled);
    ~ProgressBar();
    // Thread-safe; redraws at most ten times a second.
    void update(double fraction);
    // Clears the bar's line.
    void finish();

private:
    bool enabled_;
    bool drawn_ = false;
    std::mutex mutex_;
    std::chrono::steady_clock::time_point start_, lastDraw_;
};

}  // namespace ray
