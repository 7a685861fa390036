#include "core/memory_limits.h"

#include <sys/resource.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace ray {

namespace {

std::optional<uint64_t> memAvailableFromProc() {
    std::ifstream in("/proc/meminfo");
    std::string key;
    uint64_t kib = 0;
    std::string unit;
    while (in >> key >> kib >> unit)
        if (key == "MemAvailable:") return kib * 1024;
    return std::nullopt;
}

// cgroup v2: what the container may still use ("max" means no limit).
std::optional<uint64_t> cgroupHeadroom() {
    std::ifstream maxFile("/sys/fs/cgroup/memory.max"), currentFile("/sys/fs/cgroup/memory.current");
    std::string max;
    uint64_t current = 0;
    if (!(maxFile >> max) || max == "max" || !(currentFile >> current)) return std::nullopt;
    auto limit = parseByteCount(max);
    if (!limit) return std::nullopt;
    return *limit > current ? *limit - current : 0;
}

void keepSmaller(std::optional<uint64_t>& best, std::optional<uint64_t> candidate) {
    if (candidate && (!best || *candidate < *best)) best = candidate;
}

}  // namespace

std::optional<uint64_t> parseByteCount(const std::string& text) {
    if (text.empty() || !std::isdigit(static_cast<unsigned char>(text[0]))) return std::nullopt;
    size_t used = 0;
    unsigned long long value = 0;
    try {
        value = std::stoull(text, &used);
    } catch (const std::exception&) {
        return std::nullopt;
    }
    std::string suffix = text.substr(used);
    int shift = 0;
    if (suffix == "K" || suffix == "k") shift = 10;
    else if (suffix == "M" || suffix == "m") shift = 20;
    else if (suffix == "G" || suffix == "g") shift = 30;
    else if (!suffix.empty()) return std::nullopt;
    if (value > (~0ull >> shift)) return std::nullopt;
    return uint64_t(value) << shift;
}

std::optional<uint64_t> availableHostMemory() {
    std::optional<uint64_t> available;
    keepSmaller(available, memAvailableFromProc());
    keepSmaller(available, cgroupHeadroom());
    if (const char* cap = std::getenv("RAY_MEMORY_LIMIT")) keepSmaller(available, parseByteCount(cap));
    return available;
}

std::string describeBytes(uint64_t bytes) {
    char text[64];
    if (bytes >= (uint64_t(1) << 30)) std::snprintf(text, sizeof text, "%.1f GiB", double(bytes) / double(1 << 30));
    else std::snprintf(text, sizeof text, "%llu MiB", (unsigned long long)((bytes + (1 << 20) - 1) >> 20));
    return text;
}

std::optional<std::string> hostMemoryShortfall(uint64_t bytes) {
    auto available = availableHostMemory();
    if (!available || bytes <= *available) return std::nullopt;
    return "needs about " + describeBytes(bytes) + " of memory, but only " + describeBytes(*available) +
           " is available" + (std::getenv("RAY_MEMORY_LIMIT") ? " (RAY_MEMORY_LIMIT counts)" : "");
}

uint64_t peakResidentBytes() {
    struct rusage usage {};
    if (::getrusage(RUSAGE_SELF, &usage) != 0 || usage.ru_maxrss < 0) return 0;
    return uint64_t(usage.ru_maxrss) * 1024;  // Linux counts kilobytes
}

}  // namespace ray
