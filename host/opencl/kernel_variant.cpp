#include "opencl/kernel_variant.h"

namespace ray {

std::string KernelVariant::buildDefine() const {
    return cpuThreads ? " -DRAY_CPU_LANES=" + std::to_string(lanes) : "";
}

KernelVariant kernelVariantFor(const OpenClDevice& device, std::optional<int> cpuLanes) {
    if (!device.isCpu || device.isGpu || device.isLlvmpipe) return {};
    const unsigned width = device.nativeFloatWidth;
    const int nativeLanes = width >= 16 ? 16 : width >= 8 ? 8 : width >= 4 ? 4 : 1;
    return {.cpuThreads = true, .lanes = cpuLanes.value_or(nativeLanes)};
}

}  // namespace ray
