// Estimating memory before allocating it, so that work too big for this machine is refused
// up front with a message, instead of ending in the kernel's out-of-memory killer halfway.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace ray {

// Host memory one flattened primitive instance costs from loading to rendering: the
// PrimitiveInstance (~208 bytes), its packed copy, BVH nodes and the BVH build's
// temporaries; another device's copy only on a GPU (a CPU OpenCL device reads the packed
// tables in place). Measured: recursiveSpheres10 (2.9 million instances) peaks at 1.5 GB
// on PoCL, 1.26 GB on the reference.
constexpr uint64_t kHostBytesPerInstance = 640;

// Host memory per image pixel: the float image (12) and the 8-bit copy written out (3).
// An 8-bit output rendered on OpenCL devices needs less (RenderJob::eightBit: its 3 bytes
// and the encoded file); the reference renderer and MPI's rank 0 keep floats. OpenCL
// devices add a few tiles' buffers, whatever the image's size (opencl/scene_upload.cpp).
constexpr uint64_t kHostBytesPerPixel = 15;

// The memory ray may plan to use: MemAvailable from /proc/meminfo, capped by the cgroup's
// memory.max when there is one, and by $RAY_MEMORY_LIMIT (bytes, or with a K, M or G
// suffix) when set; nullopt when none of these can be read (nothing is refused then).
std::optional<uint64_t> availableHostMemory();

// "1.5 GiB", "300 MiB": for messages.
std::string describeBytes(uint64_t bytes);

// When `bytes` exceeds availableHostMemory(): "needs about X, but only Y of memory is
// available"; nullopt when it fits (or nothing is known).
std::optional<std::string> hostMemoryShortfall(uint64_t bytes);

// The most resident memory the process has held so far (getrusage's ru_maxrss), in bytes;
// 0 where the system does not say.
uint64_t peakResidentBytes();

// Parses "512", "300M", "2G" (powers of 1024); nullopt for anything else.
std::optional<uint64_t> parseByteCount(const std::string& text);

}  // namespace ray
