// The error of a render device or runtime, thrown by the OpenCL engine and the device
// selection alike, caught by every command and translated by the public API.
#pragma once

#include <stdexcept>

namespace ray {

// A device or runtime failure (no OpenCL platform, a kernel that fails to build, a scene
// too big for the device): the message says what happened and what to try instead.
struct DeviceError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace ray
