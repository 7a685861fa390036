#include "opencl/frame_deadlines.h"

#include <algorithm>
#include <cstdio>

namespace ray::engine {

namespace {

Clock::duration inClockTicks(double seconds) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

bool late(const Frame& frame, const Frame::Participant& device, Clock::time_point now) {
    auto d = deadlineOf(frame, device);
    return d && *d < now;
}

}  // namespace

std::optional<Clock::time_point> deadlineOf(const Frame& frame, const Frame::Participant& p) {
    if (p.part != Frame::Part::Rendering || p.flights.empty()) return std::nullopt;
    const Clock::time_point since = std::max(p.flights.front().launched, p.lastAnswer);
    if (!p.warm) return since + inClockTicks(kWarmUpSeconds);
    double seconds =
        std::max(kDeadlineFloorSeconds, kDeadlineFactor * std::max(frame.slowestTileSeconds, p.slowestTileSeconds));
    return since + inClockTicks(seconds);
}

std::optional<Clock::time_point> nextDeadline(const Frame& frame, Clock::time_point now) {
    std::optional<Clock::time_point> next;
    for (const Frame::Participant& p : frame.devices)
        if (auto d = deadlineOf(frame, p); d && *d > now && (!next || *d < *next)) next = d;
    return next;
}

std::vector<SilentDevice> dropLateDevices(Frame& frame, Clock::time_point now) {
    using Part = Frame::Part;
    std::vector<SilentDevice> dropped;
    for (size_t i = 0; i < frame.devices.size(); ++i) {
        Frame::Participant& p = frame.devices[i];
        if (!late(frame, p, now)) continue;
        bool another = false;
        for (size_t j = 0; j < frame.devices.size(); ++j) {
            const Frame::Participant& q = frame.devices[j];
            const bool in = q.part == Part::Preparing || q.part == Part::Rendering || q.part == Part::Left;
            if (j != i && in && !late(frame, q, now)) another = true;
        }
        if (!another) continue;
        const Clock::time_point since = std::max(p.flights.front().launched, p.lastAnswer);
        dropped.push_back({int(i), std::chrono::duration<double>(now - since).count()});
        frame.scheduler->drop(int(i));  // its tiles go to the others; its late answer still counts if first
        p.flights.clear();
        p.part = Part::Hung;
        --frame.devicesLeft;
        frame.changed.notify_all();
    }
    return dropped;
}

std::string hungMessage(double silentSeconds) {
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.1f", silentSeconds);
    return "stopped answering: no tile back in " + std::string(seconds) + " s, past its deadline (" +
           std::to_string(int(kDeadlineFactor)) + " times the slowest tile, at least " +
           std::to_string(int(kDeadlineFloorSeconds)) +
           " s); its tiles went to the other devices, and ray does not wait for it";
}

}  // namespace ray::engine
