// Helpers shared by the libFuzzer targets (see scripts/fuzz.sh and docs/user-guide.md,
// "Hostile input and limits").
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

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

// A property the target checks does not hold: says which and what, then aborts, which
// libFuzzer reports as a crash with the input saved.
[[noreturn]] inline void fail(const std::string& what, const std::string& detail, const std::string& text = "") {
    std::fprintf(stderr, "fuzz property failed: %s: %s\n", what.c_str(), detail.c_str());
    if (!text.empty()) std::fprintf(stderr, "--- the text ---\n%.4000s\n--- end ---\n", text.c_str());
    std::abort();
}

// Makes libFuzzer's malloc limit the product's own: an allocation of more than `bytes` is a
// crash, since ray promises never to make one (for images, decode_limits.h). Called from
// LLVMFuzzerInitialize, which libFuzzer runs before it reads its flags, so the flag is added
// to the command line unless the caller gave one.
inline void limitMallocTo(uint64_t bytes, int* argc, char*** argv) {
    for (int i = 1; i < *argc; ++i)
        if (std::strncmp((*argv)[i], "-malloc_limit_mb=", 17) == 0) return;
    static std::vector<char*> arguments;
    static std::string flag;
    flag = "-malloc_limit_mb=" + std::to_string((bytes + (1u << 20) - 1) >> 20);
    arguments.assign(*argv, *argv + *argc);
    arguments.push_back(flag.data());
    arguments.push_back(nullptr);
    *argc = int(arguments.size()) - 1;
    *argv = arguments.data();
}

}  // namespace ray::fuzz
