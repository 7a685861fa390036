#include "viewer/file_stamp.h"

namespace ray {

bool FileStamp::operator==(const FileStamp& other) const {
    return exists == other.exists && device == other.device && inode == other.inode && type == other.type &&
           size == other.size && modified.tv_sec == other.modified.tv_sec &&
           modified.tv_nsec == other.modified.tv_nsec;
}

FileStamp stampOf(const std::filesystem::path& file) {
    struct stat info {};
    if (stat(file.c_str(), &info) != 0) return {};
    return {true, info.st_dev, info.st_ino, mode_t(info.st_mode & S_IFMT), info.st_size, info.st_mtim};
}

std::optional<std::string> notRegularFile(const FileStamp& stamp) {
    if (!stamp.exists || stamp.type == S_IFREG) return std::nullopt;
    switch (stamp.type) {
        case S_IFIFO: return "is a FIFO (a named pipe), not a regular file";
        case S_IFDIR: return "is a folder, not a regular file";
        case S_IFCHR: return "is a character device, not a regular file";
        case S_IFBLK: return "is a block device, not a regular file";
        case S_IFSOCK: return "is a socket, not a regular file";
        default: return "is not a regular file";
    }
}

}  // namespace ray
