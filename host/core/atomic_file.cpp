// Atomic file writes: a temporary file beside the target, checked, fsync'd, renamed.
#include "core/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <string>
#include <thread>

#include "core/test_hooks.h"

namespace ray {
namespace fs = std::filesystem;

namespace {

std::string systemReason(int error) { return std::strerror(error); }

[[noreturn]] void fail(const fs::path& target, const std::string& what, int error) {
    throw FileWriteError(target.string() + ": cannot write: " + what + ": " + systemReason(error));
}

// ".<stem>.tmp<pid>-<n><ext>" beside the target: hidden, unique within and across
// processes, and with the target's extension (encoders choose the format by it).
fs::path temporaryName(const fs::path& target) {
    static std::atomic<unsigned> counter{0};
    std::string name = ".";  // appended piecewise: "." + string trips GCC 12's -Wrestrict
    name += target.stem().string();
    name += ".tmp";
    name += std::to_string(getpid());
    name += '-';
    name += std::to_string(counter++);
    name += target.extension().string();
    fs::path tmp = target;
    tmp.replace_filename(name);
    return tmp;
}

// Creates the temporary file exclusively (never follows or reuses someone else's file).
// Mode 0666 less the umask, what the target would get from a plain open().
int createTemporary(const fs::path& target, fs::path& tmp) {
    for (int attempt = 0; attempt < 100; ++attempt) {
        tmp = temporaryName(target);
        int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) return fd;
        if (errno != EEXIST) fail(target, "cannot create the temporary file " + tmp.string(), errno);
    }
    fail(target, "cannot create a temporary file beside it", EEXIST);
}

// Test hook (tests/fault_injection.sh): a pause halfway through the write, so that a test can
// kill -9 the process while the temporary file is half written (core/test_hooks.h).
void pauseForTestHook() {
    if (const int ms = testHooks().writePauseMs; ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(ms));
}

// write() until every byte is out: it may write less than asked, or be interrupted.
bool writeAll(int fd, const char* data, size_t size) {
    while (size > 0) {
        ssize_t n = ::write(fd, data, size);
        if (n < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        data += n;
        size -= size_t(n);
    }
    return true;
}

// The temporary file removed on every path that does not end in the rename.
struct TemporaryFile {
    fs::path path;
    int fd = -1;
    bool committed = false;
    ~TemporaryFile() {
        if (fd >= 0) ::close(fd);
        if (!committed && !path.empty()) ::unlink(path.c_str());
    }
};

void syncCloseAndRename(const fs::path& target, TemporaryFile& tmp) {
    if (::fsync(tmp.fd) != 0) fail(target, "fsync of " + tmp.path.string(), errno);
    const int fd = tmp.fd;
    tmp.fd = -1;
    if (::close(fd) != 0) fail(target, "close of " + tmp.path.string(), errno);
    if (::rename(tmp.path.c_str(), target.c_str()) != 0) fail(target, "rename of " + tmp.path.string(), errno);
    tmp.committed = true;
    // Make the rename itself durable. Best effort: the file is complete and in place
    // already, and some file systems refuse fsync on a directory.
    fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    int dirFd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dirFd >= 0) {
        (void)::fsync(dirFd);
        ::close(dirFd);
    }
}

}  // namespace

void writeFileAtomically(const fs::path& target, std::string_view bytes) {
    TemporaryFile tmp;
    tmp.fd = createTemporary(target, tmp.path);
    const size_t half = bytes.size() / 2;
    if (!writeAll(tmp.fd, bytes.data(), half)) fail(target, "write to " + tmp.path.string(), errno);
    pauseForTestHook();
    if (!writeAll(tmp.fd, bytes.data() + half, bytes.size() - half))
        fail(target, "write to " + tmp.path.string(), errno);
    syncCloseAndRename(target, tmp);
}

void writeFileAtomicallyVia(const fs::path& target, const std::function<void(const fs::path&)>& writeTemporary) {
    TemporaryFile tmp;
    tmp.fd = createTemporary(target, tmp.path);  // reserves the name; the encoder rewrites it
    writeTemporary(tmp.path);
    pauseForTestHook();
    // The encoder closed its own handle; fsync needs one that sees the same file.
    ::close(tmp.fd);
    tmp.fd = ::open(tmp.path.c_str(), O_RDONLY | O_CLOEXEC);
    if (tmp.fd < 0) fail(target, "reopening " + tmp.path.string(), errno);
    syncCloseAndRename(target, tmp);
}

void checkCanWriteBeside(const fs::path& target) {
    fs::path tmp;
    const int fd = createTemporary(target, tmp);
    ::close(fd);
    ::unlink(tmp.c_str());
}

}  // namespace ray
