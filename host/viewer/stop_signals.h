// How `ray view` stops: SIGINT (Ctrl-C), SIGTERM and SIGHUP (a closed terminal) are taken by
// one thread of their own, which runs what the viewer asked to be done first (keep unsaved
// edits: viewer/recovery.h), then ends the process with the usual status, 128 + the
// signal's number (130, 143, 129). A second signal while that runs ends it at once.
#pragma once

#include <functional>

namespace ray {

class StopSignals {
public:
    // Blocks the signals in this thread and every thread started after it (so that only
    // the waiting thread takes them): make it before any other thread starts.
    StopSignals();
    // Ends the waiting thread and unblocks the signals.
    ~StopSignals();
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;

    // What a stop does before the process exits (replacing what was set before); none: it
    // exits at once. Called on the waiting thread with the signal's number.
    static void beforeExit(std::function<void(int signal)> action);
};

}  // namespace ray
