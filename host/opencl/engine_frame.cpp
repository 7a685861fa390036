#include "opencl/engine_frame.h"

namespace ray::engine {

bool Frame::over() const {
    if (sourceCallers > 0) return false;
    if (devicesLeft == 0) return true;
    if (!allDone() && !cancelled()) return false;
    for (const Participant& p : devices)
        if (p.part == Part::Rendering && p.warm && !p.flights.empty()) return false;
    return true;
}

void Frame::deviceFailed(int index) {
    Participant& p = devices[size_t(index)];
    if (p.part != Part::Preparing && p.part != Part::Rendering) return;
    scheduler->giveBack(index);
    p.flights.clear();
    p.part = Part::Failed;
    --devicesLeft;
    changed.notify_all();
}

}  // namespace ray::engine
