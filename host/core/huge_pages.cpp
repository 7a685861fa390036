#include "core/huge_pages.h"

#include <unistd.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace ray {
namespace {

constexpr const char* kTunable = "glibc.malloc.hugetlb";

// Whether madvise(MADV_HUGEPAGE) gets huge pages: the kernel's setting is "always" or
// "madvise" (the selected one is in brackets), not "never" or absent.
bool kernelGivesHugePages() {
    std::ifstream setting("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string line;
    if (!std::getline(setting, line)) return false;
    return line.find("[always]") != std::string::npos || line.find("[madvise]") != std::string::npos;
}

// Whether malloc is glibc's own, 2.35 or later (the first with the tunable): under
// AddressSanitizer it is the sanitizer's, which reads no tunable.
constexpr bool glibcMallocWithTunable() {
#if defined(__SANITIZE_ADDRESS__)
    return false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
    return false;
#endif
#endif
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 35))
    return true;
#else
    return false;
#endif
}

}  // namespace

void restartWithHugePageHeap(char** argv) {
    if constexpr (!glibcMallocWithTunable()) return;
    const char* wanted = std::getenv("RAY_HUGE_PAGES");
    if (wanted && std::strcmp(wanted, "0") == 0) return;
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    if (tunables && std::strstr(tunables, kTunable)) return;  // ours, or the user's choice
    if (!kernelGivesHugePages()) return;
    std::string value = std::string(kTunable) + "=1";
    if (tunables && *tunables) value = std::string(tunables) + ":" + value;
    // The program's own path, not /proc/self/exe: the process is named after the file
    // exec'd, and ps, pgrep and top would call it "exe".
    std::error_code error;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
    if (error) return;
    if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
    execv(self.c_str(), argv);
    // Not replaced (no /proc, say): run on as we are. The variable stays, so that a program
    // this one starts does not try again.
}

void returnLargeBlocksWhenFreed() {
    // Setting the threshold also ends its raising (mallopt(3), M_MMAP_THRESHOLD).
    if constexpr (glibcMallocWithTunable()) {
#if defined(__GLIBC__)
        mallopt(M_MMAP_THRESHOLD, int(kLargeBlockBytes));
#endif
    }
}

}  // namespace ray
