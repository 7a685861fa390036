// Which variant of the kernel a device runs (cl/device/variant.h): decided here, once, from
// what the device is, and passed to the kernel's build as its one define. The host's own
// choices follow from the same answer: the launches (a pixel or a block of pixels a
// work-item), the kernel's arguments and the tables packed and uploaded for the device.
#pragma once

#include <optional>
#include <string>

#include "opencl/opencl_device.h"
#include "opencl/scene_packing.h"

namespace ray {

struct KernelVariant {
    // A CPU device whose work-items are threads (PoCL): its kernel walks the sixteen-wide
    // tree (PackedScene::cpuNodes) a ray at a time and keeps some helpers calls. Otherwise
    // the work-items run in SIMT lanes (a GPU, Mesa's llvmpipe), one ray each.
    bool cpuThreads = false;
    // Rays a work-item traces together: 1, or on a CPU device 4, 8 or 16, its packets.
    int lanes = 1;

    // The build option that says so: " -DRAY_CPU_LANES=n" on a CPU device, else nothing.
    std::string buildDefine() const;
    // Whether the kernel reads the scene buffer `buffer` (cl/shared_types.h RAY_SCENE_BUFFERS):
    // a table read only by CPU devices is neither packed nor uploaded for the others.
    bool reads(const SceneBufferName& buffer) const { return !buffer.cpuOnly || cpuThreads; }
};

// The variant for `device`: a CPU's for a CPU device, a GPU's for every other. On a CPU
// device, `cpuLanes` (the test hook RAY_CPU_PACKETS: 1 for one ray a work-item, or 4, 8 or
// 16) sets the rays a work-item traces; without it, packets of the device's native float
// width (16 with AVX-512, 8 with AVX2, 4 with SSE), since PoCL runs a one-ray walk as scalar
// code. Two CPU devices count as GPUs: Mesa's llvmpipe, which runs work-items in SIMT lanes
// as a GPU does (and stands in for one in tests/rusticl.sh), and a device that says it is a
// GPU as well (Oclgrind says it is every kind; tests/oclgrind.sh checks the GPU's kernel).
KernelVariant kernelVariantFor(const OpenClDevice& device, std::optional<int> cpuLanes = std::nullopt);

}  // namespace ray
