// How many primitives a scene flattens to, read from its XML without building anything,
// so that the bench can decide which scenes the (slower) reference renderer should try.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>

namespace bench {

// The number of primitive instances the root tree flattens to (masters expanded), or
// nullopt when the file cannot be read or its masters are undefined or cyclic.
std::optional<uint64_t> countPrimitives(const std::filesystem::path& scene);

}  // namespace bench
