// When a device of a frame counts as hung (opencl_engine.h): one with tiles in flight that
// sends none back within its deadline, while another device still answers. The deadline runs
// from its oldest launch or its last answer, whichever is later: kDeadlineFactor times the
// slowest tile seen (this frame's on any device, or the device's own before), and at least
// kDeadlineFloorSeconds (a machine busy with other work, a tile far heavier than those before
// it). A device's first tile with a program also compiles it for the launch (PoCL: about 14 s
// for this kernel, cold, on a loaded 2-core machine), so it gets kWarmUpSeconds, and a frame
// never waits for it. When every device is late at once, the machine stalled (a suspend):
// none is dropped. The ranks of mpirun have deadlines of their own, the tile scheduler's.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "opencl/engine_frame.h"

namespace ray::engine {

constexpr double kDeadlineFactor = 10;
constexpr double kDeadlineFloorSeconds = 10;
constexpr double kWarmUpSeconds = 300;

// When the device counts as hung if no tile comes back: nothing while it has none in flight.
std::optional<Clock::time_point> deadlineOf(const Frame& frame, const Frame::Participant& device);

// The next moment a deadline passes after `now`, if any device has one ahead.
std::optional<Clock::time_point> nextDeadline(const Frame& frame, Clock::time_point now);

// Drops the devices past their deadline while another device is in the frame and not late
// itself (a device that is the last one left is waited for: no other could take its tiles):
// their tiles go to the others, and a late answer of theirs still counts if it is the first.
// Returns them, with how long each was silent. Under the frame's lock.
struct SilentDevice {
    int device;
    double seconds;
};
std::vector<SilentDevice> dropLateDevices(Frame& frame, Clock::time_point now);

// Why a device was dropped as hung, for its warning.
std::string hungMessage(double silentSeconds);

}  // namespace ray::engine
