// Opening a file ray reads (core/input_file.h): a regular file of a size its kind justifies.
#include "core/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace ray {

namespace {

std::string kindOf(mode_t mode) {
    if (S_ISDIR(mode)) return "a folder";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "something else";
}

std::string megabytes(uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

// The checks on what stat said.
void checkStatus(const std::filesystem::path& file, const struct stat& status, const InputLimit& limit) {
    if (!S_ISREG(status.st_mode))
        throw InputFileError(file, std::string("cannot read ") + limit.what + ": it is not a regular file (" +
                                       kindOf(status.st_mode) + "); name a file");
    if (uint64_t(status.st_size) > limit.maxBytes)
        throw InputFileError(file, std::string("cannot read ") + limit.what + ": it holds " +
                                       megabytes(uint64_t(status.st_size)) + ", more than " + limit.what +
                                       " can need (" + megabytes(limit.maxBytes) + ": " + limit.why +
                                       "); is it the right file?");
}

[[noreturn]] void systemFailure(const std::filesystem::path& file, const InputLimit& limit, int error) {
    throw InputFileError(file, std::string("cannot read ") + limit.what + ": " + std::strerror(error));
}

}  // namespace

uint64_t checkInputFile(const std::filesystem::path& file, const InputLimit& limit) {
    struct stat status {};
    if (::stat(file.c_str(), &status) != 0) systemFailure(file, limit, errno);
    checkStatus(file, status, limit);
    return uint64_t(status.st_size);
}

std::string readInputFile(const std::filesystem::path& file, const InputLimit& limit) {
    // O_NONBLOCK: opening a FIFO must not wait for a writer; it is refused just below.
    const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC | (limit.refuseLink ? O_NOFOLLOW : 0));
    if (fd < 0 && errno == ELOOP && limit.refuseLink)
        throw InputFileError(file, std::string("cannot be opened: it is a symbolic link, and ") + limit.what +
                                       " is read from no link");
    if (fd < 0) systemFailure(file, limit, errno);
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat status {};
    if (::fstat(fd, &status) != 0) systemFailure(file, limit, errno);
    checkStatus(file, status, limit);
    std::string bytes(size_t(status.st_size), '\0');
    size_t done = 0;
    while (done < bytes.size()) {  // a file that shrank meanwhile ends early; one that grew is cut at its size
        const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) systemFailure(file, limit, errno);
        if (n == 0) break;
        done += size_t(n);
    }
    bytes.resize(done);
    return bytes;
}

}  // namespace ray
