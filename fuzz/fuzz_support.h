// Helpers shared by the libFuzzer targets (see scripts/fuzz.sh and docs/user-guide.md,
// "Hostile input and limits").
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace ray::fuzz {

// A private folder for the files a target writes or reads, made once per process and
// left in /tmp (or $TMPDIR) for the operating system to clean; /dev/shm when there is one,
// since every execution writes a file.
inline const std::filesystem::path& scratchFolder() {
    static const std::filesystem::path folder = [] {
        std::string base = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
        if (const char* tmp = std::getenv("TMPDIR")) base = tmp;
        std::string pattern = base + "/ray-fuzz-XXXXXX";
        if (!mkdtemp(pattern.data())) std::abort();
        return std::filesystem::path(pattern);
    }();
    return folder;
}

inline void writeBytes(const std::filesystem::path& file, const uint8_t* data, size_t size) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

}  // namespace ray::fuzz
