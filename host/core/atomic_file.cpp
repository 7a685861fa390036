// The one writer (core/atomic_file.h): what the target is, then how it is written.
#include "core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <optional>
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

[[noreturn]] void refuse(const fs::path& target, const std::string& sentence) {
    throw OutputRefused(target.string() + ": " + sentence);
}

// ---------------------------------------------------------------------------------------
// What the target is

enum class TargetKind {
    NewFile,      // nothing there yet: created atomically
    RegularFile,  // replaced atomically, keeping its mode and owner
    Stream,       // a character device or FIFO: opened and written into
    Descriptor,   // one of this process's descriptors (/dev/stdout): written into
};

struct Target {
    fs::path path;  // the final path, after symbolic links
    TargetKind kind = TargetKind::NewFile;
    struct stat status {};  // of `path`, when it exists
    int descriptor = -1;    // for Descriptor
};

// "/dev/stdout", "/dev/fd/3", "/proc/self/fd/3", "/proc/<our pid>/fd/3": the descriptor, else
// nothing. Read as text: following /proc/self/fd/1 would lead to whatever the shell opened
// (a file, a pipe), which must be written through the descriptor, at its offset, not
// replaced or reopened from the start.
std::optional<int> ownDescriptorNamed(const fs::path& path) {
    const std::string text = path.lexically_normal().string();
    if (text == "/dev/stdin") return 0;
    if (text == "/dev/stdout") return 1;
    if (text == "/dev/stderr") return 2;
    const std::string prefixes[] = {"/dev/fd/", "/proc/self/fd/", "/proc/thread-self/fd/",
                                    "/proc/" + std::to_string(getpid()) + "/fd/"};
    for (const std::string& prefix : prefixes) {
        if (text.rfind(prefix, 0) != 0) continue;
        const char* first = text.data() + prefix.size();
        const char* last = text.data() + text.size();
        int fd = -1;
        auto [end, ec] = std::from_chars(first, last, fd);
        if (ec == std::errc() && end == last && first != last) return fd;
    }
    return std::nullopt;
}

std::string kindName(mode_t mode) {
    if (S_ISDIR(mode)) return "a folder";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a file";
}

// Follows symbolic links to the final target (at most 40, the kernel's own limit), then
// says what is there. Throws OutputRefused for what is never written.
Target resolveTarget(const fs::path& given) {
    Target target;
    fs::path path = given;
    for (int hops = 0;; ++hops) {
        if (std::optional<int> fd = ownDescriptorNamed(path)) {
            if (::fcntl(*fd, F_GETFD) < 0)
                refuse(given, "names descriptor " + std::to_string(*fd) + ", which ray was not given open; name a file");
            target.path = path;
            target.kind = TargetKind::Descriptor;
            target.descriptor = *fd;
            return target;
        }
        if (::lstat(path.c_str(), &target.status) != 0) {
            if (errno != ENOENT) fail(given, "cannot look at " + path.string(), errno);
            target.path = path;  // nothing there (a dangling link's target): made new
            target.kind = TargetKind::NewFile;
            return target;
        }
        if (!S_ISLNK(target.status.st_mode)) break;
        if (hops == 40) refuse(given, "too many symbolic links (a loop?); name the file itself");
        std::error_code ec;
        const fs::path link = fs::read_symlink(path, ec);
        if (ec) fail(given, "cannot read the symbolic link " + path.string(), ec.value());
        path = link.is_absolute() ? link : path.parent_path() / link;
    }
    target.path = path;
    const mode_t mode = target.status.st_mode;
    if (S_ISREG(mode)) {
        target.kind = TargetKind::RegularFile;
    } else if (S_ISCHR(mode) || S_ISFIFO(mode)) {
        target.kind = TargetKind::Stream;
    } else {
        const std::string through = path == given ? "" : " (through a symbolic link to " + path.string() + ")";
        refuse(given, "is " + kindName(mode) + through + ", not a file ray can write; name a file" +
                          (S_ISDIR(mode) ? " in it, such as " + (given / "out").string() + " with the extension you want"
                                         : ""));
    }
    return target;
}

// No write permission for the user (for root, who may write anything: no owner write bit).
bool isReadOnly(const Target& target) {
    if ((target.status.st_mode & S_IWUSR) == 0) return true;
    return ::access(target.path.c_str(), W_OK) != 0 && errno == EACCES;
}

std::string octalMode(mode_t mode) {
    char text[8];
    std::snprintf(text, sizeof text, "%03o", unsigned(mode & 07777));
    return text;
}

void refuseReadOnly(const fs::path& given, const Target& target, const WriteOptions& options) {
    if (options.replaceReadOnly || !isReadOnly(target)) return;
    const std::string through = target.path == given ? "" : " (through a symbolic link to " + target.path.string() + ")";
    refuse(given, "is read-only" + through + " (mode " + octalMode(target.status.st_mode) +
                      "); ray does not replace it unless told to: make it writable (chmod u+w " +
                      target.path.string() + "), name another file, or add " + options.replaceReadOnlyHint);
}

void warn(const WriteOptions& options, const std::string& message) {
    if (options.warn)
        options.warn(message);
    else
        std::cerr << "ray: warning: " << message << "\n";
}

void noteHardLinks(const fs::path& given, const Target& target, const WriteOptions& options) {
    const auto links = target.status.st_nlink;
    if (links <= 1) return;
    warn(options, given.string() + " had " + std::to_string(links) + " hard links; it was replaced by a new file, so " +
                      std::to_string(links - 1) + (links == 2 ? " other name keeps" : " other names keep") +
                      " the old contents");
}

// ---------------------------------------------------------------------------------------
// Writing

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

// Test hook (tests/fault_injection.sh): a pause halfway through the write, so that a test can
// kill -9 the process while the temporary file is half written (core/test_hooks.h).
void pauseForTestHook() {
    if (const int ms = testHooks().writePauseMs; ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(ms));
}

// The bytes in two halves, the test hook's pause between them.
void writeInHalves(int fd, std::string_view bytes, const fs::path& given, const std::string& into) {
    const size_t half = bytes.size() / 2;
    if (!writeAll(fd, bytes.data(), half)) fail(given, "write to " + into, errno);
    pauseForTestHook();
    if (!writeAll(fd, bytes.data() + half, bytes.size() - half)) fail(given, "write to " + into, errno);
}

// ".<stem>.tmp<pid>-<n><ext>" beside `path`: hidden, unique within and across processes, and
// with the extension (encoders choose the format by it).
fs::path temporaryName(const fs::path& path) {
    static std::atomic<unsigned> counter{0};
    std::string name = ".";  // appended piecewise: "." + string trips GCC 12's -Wrestrict
    name += path.stem().string();
    name += ".tmp";
    name += std::to_string(getpid());
    name += '-';
    name += std::to_string(counter++);
    name += path.extension().string();
    fs::path tmp = path;
    tmp.replace_filename(name);
    return tmp;
}

// A temporary file, removed on every path that does not end in its rename.
struct TemporaryFile {
    fs::path path;
    int fd = -1;
    bool committed = false;
    TemporaryFile() = default;
    TemporaryFile(const TemporaryFile&) = delete;
    TemporaryFile& operator=(const TemporaryFile&) = delete;
    ~TemporaryFile() {
        if (fd >= 0) ::close(fd);
        if (!committed && !path.empty()) ::unlink(path.c_str());
    }
};

// Creates a temporary file beside `besides` exclusively (never follows or reuses someone
// else's file): mode 0666 less the umask for a new file, what a plain open() would give it;
// 0600 while it is written for a file that replaces another (its mode is copied at the end).
void createTemporaryBeside(const fs::path& besides, const fs::path& given, mode_t mode, TemporaryFile& tmp) {
    for (int attempt = 0; attempt < 100; ++attempt) {
        tmp.path = temporaryName(besides);
        tmp.fd = ::open(tmp.path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, mode);
        if (tmp.fd >= 0) return;
        if (errno != EEXIST) {
            const int error = errno;
            tmp.path.clear();
            const fs::path folder = besides.parent_path();
            if (error == ENOENT && !folder.empty())
                refuse(given, "cannot write: the folder " + folder.string() + " does not exist (" + systemReason(error) +
                                  "); create it or name another");
            fail(given, "cannot create the temporary file " + temporaryName(besides).string(), error);
        }
    }
    tmp.path.clear();
    fail(given, "cannot create a temporary file beside it", EEXIST);
}

// The replaced file's owner and mode onto the new one. The owner first (a chown clears
// set-id bits), and only where the system allows it: root may give the file to anyone, a
// user may change its group to one of theirs; otherwise the file becomes the user's, as any
// new file would.
void keepOwnerAndMode(int fd, const struct stat& old) {
    struct stat now {};
    if (::fstat(fd, &now) == 0 && (now.st_uid != old.st_uid || now.st_gid != old.st_gid))
        if (::fchown(fd, old.st_uid, old.st_gid) != 0) (void)::fchown(fd, uid_t(-1), old.st_gid);
    (void)::fchmod(fd, old.st_mode & 07777);
}

// Makes a rename durable. Best effort: the file is complete and in place already, and some
// file systems refuse fsync on a folder.
void syncFolder(const fs::path& file) {
    const fs::path folder = file.parent_path().empty() ? fs::path(".") : file.parent_path();
    const int dirFd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dirFd >= 0) {
        (void)::fsync(dirFd);
        ::close(dirFd);
    }
}

void syncCloseAndRename(const fs::path& given, const Target& target, TemporaryFile& tmp) {
    if (target.kind == TargetKind::RegularFile) keepOwnerAndMode(tmp.fd, target.status);
    if (::fsync(tmp.fd) != 0) fail(given, "fsync of " + tmp.path.string(), errno);
    const int fd = tmp.fd;
    tmp.fd = -1;
    if (::close(fd) != 0) fail(given, "close of " + tmp.path.string(), errno);
    if (::rename(tmp.path.c_str(), target.path.c_str()) != 0) fail(given, "rename of " + tmp.path.string(), errno);
    tmp.committed = true;
    syncFolder(target.path);
}

// Opens a character device or FIFO for writing. A FIFO is opened without blocking (a FIFO
// nobody reads would hang ray for ever), retried while no reader has it open, up to
// kFifoReaderWait; then writes block as usual, at the reader's pace.
int openStream(const fs::path& given, const Target& target) {
    const bool fifo = S_ISFIFO(target.status.st_mode);
    const int flags = O_WRONLY | O_NOCTTY | O_CLOEXEC | (fifo ? O_NONBLOCK : 0);
    const auto deadline = std::chrono::steady_clock::now() + kFifoReaderWait;
    for (;;) {
        const int fd = ::open(target.path.c_str(), flags);
        if (fd >= 0) {
            if (fifo) ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
            return fd;
        }
        if (errno == EINTR) continue;
        if (!(fifo && errno == ENXIO)) fail(given, "cannot open " + target.path.string(), errno);
        if (std::chrono::steady_clock::now() >= deadline)
            refuse(given, "is a FIFO that no program opened for reading within " +
                              std::to_string(kFifoReaderWait.count()) + " s; start its reader first");
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

struct Descriptor {
    int fd = -1;
    bool owned = false;  // opened here (a stream), not the process's own (stdout)
    Descriptor() = default;
    Descriptor(const Descriptor&) = delete;
    Descriptor& operator=(const Descriptor&) = delete;
    ~Descriptor() {
        if (owned && fd >= 0) ::close(fd);
    }
};

// The descriptor a stream or descriptor target is written through.
void openWritable(const fs::path& given, const Target& target, Descriptor& out) {
    if (target.kind == TargetKind::Descriptor) {
        out.fd = target.descriptor;
        return;
    }
    out.fd = openStream(given, target);
    out.owned = true;
}

void closeWritable(const fs::path& given, Descriptor& d) {
    if (!d.owned) return;
    const int fd = d.fd;
    d.fd = -1;
    if (::close(fd) != 0) fail(given, "close", errno);
}

// What the writers do with each kind before writing: refusals and notes.
void prepare(const fs::path& given, const Target& target, const WriteOptions& options) {
    if (target.kind != TargetKind::RegularFile) return;
    refuseReadOnly(given, target, options);
    noteHardLinks(given, target, options);
}

bool isFile(const Target& target) { return target.kind == TargetKind::NewFile || target.kind == TargetKind::RegularFile; }

mode_t temporaryMode(const Target& target) { return target.kind == TargetKind::RegularFile ? 0600 : 0666; }

// Copies a finished file into a stream, in pieces.
void copyInto(int out, const fs::path& from, const fs::path& given) {
    const int in = ::open(from.c_str(), O_RDONLY | O_CLOEXEC);
    if (in < 0) fail(given, "reopening " + from.string(), errno);
    char buffer[1 << 16];
    for (;;) {
        const ssize_t n = ::read(in, buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            const int error = errno;
            ::close(in);
            fail(given, "reading back " + from.string(), error);
        }
        if (n == 0) break;
        if (!writeAll(out, buffer, size_t(n))) {
            const int error = errno;
            ::close(in);
            fail(given, "write", error);
        }
    }
    ::close(in);
}

}  // namespace

void writeFileAtomically(const fs::path& given, std::string_view bytes, const WriteOptions& options) {
    const Target target = resolveTarget(given);
    if (isFile(target)) {
        TemporaryFile tmp;  // first: a folder ray cannot write to is the failure to report
        createTemporaryBeside(target.path, given, temporaryMode(target), tmp);
        prepare(given, target, options);
        writeInHalves(tmp.fd, bytes, given, tmp.path.string());
        syncCloseAndRename(given, target, tmp);
        return;
    }
    Descriptor out;
    openWritable(given, target, out);
    writeInHalves(out.fd, bytes, given, target.path.string());
    closeWritable(given, out);
}

void writeFileAtomicallyVia(const fs::path& given, const std::function<void(const fs::path&)>& writeTemporary,
                            const WriteOptions& options) {
    const Target target = resolveTarget(given);
    TemporaryFile tmp;
    // A stream's encoder writes to a temporary file in the temporary folder (a device's
    // folder is no place for files), copied into the stream once it is whole.
    const fs::path beside = isFile(target) ? target.path : fs::temp_directory_path() / ("ray" + given.filename().string());
    createTemporaryBeside(beside, given, temporaryMode(target), tmp);  // reserves the name; the encoder rewrites it
    prepare(given, target, options);
    writeTemporary(tmp.path);
    pauseForTestHook();
    // The encoder closed its own handle; fsync needs one that sees the same file.
    ::close(tmp.fd);
    tmp.fd = ::open(tmp.path.c_str(), O_RDONLY | O_CLOEXEC);
    if (tmp.fd < 0) fail(given, "reopening " + tmp.path.string(), errno);
    if (isFile(target)) {
        syncCloseAndRename(given, target, tmp);
        return;
    }
    Descriptor out;
    openWritable(given, target, out);
    copyInto(out.fd, tmp.path, given);
    closeWritable(given, out);
}

void checkCanWrite(const fs::path& given, const WriteOptions& options) {
    const Target target = resolveTarget(given);
    if (!isFile(target)) return;  // opening a FIFO now would end its reader's input
    TemporaryFile tmp;  // first: a folder ray cannot write to is the failure to report
    createTemporaryBeside(target.path, given, 0600, tmp);
    if (target.kind == TargetKind::RegularFile) refuseReadOnly(given, target, options);
}

void refuseWritingOverInput(const fs::path& output, const std::string& option, const fs::path& input,
                            const std::string& what) {
    struct stat out {}, in {};
    if (::stat(output.c_str(), &out) != 0 || ::stat(input.c_str(), &in) != 0) return;
    if (!S_ISREG(out.st_mode)) return;  // a device or FIFO is written into, never replaced
    if (out.st_dev != in.st_dev || out.st_ino != in.st_ino) return;
    const std::string same = output == input ? "" : " (" + input.string() + ", through a link)";
    refuse(output, "is " + what + same + "; " + option + " would replace it. Name another file for " + option);
}

}  // namespace ray
