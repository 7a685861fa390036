// What the viewer's watcher (scene_watch.cpp) compares to notice that a file it shows changed
// on disk: the file's identity and its last change, from one stat, which never opens the file
// (a FIFO put in its place does not block it).
#pragma once

#include <sys/stat.h>

#include <filesystem>
#include <optional>
#include <string>

namespace ray {

struct FileStamp {
    bool exists = false;
    dev_t device = 0;
    ino_t inode = 0;  // a file deleted and written again is another inode, whatever its time
    mode_t type = 0;
    off_t size = 0;
    timespec modified{};

    bool operator==(const FileStamp& other) const;
    bool operator!=(const FileStamp& other) const { return !(*this == other); }
};

// The stamp of `file`, links followed; exists is false when there is nothing there.
FileStamp stampOf(const std::filesystem::path& file);

// Why a file that exists cannot be read as a scene, texture or mesh: not a regular file
// ("is a FIFO", "is a folder", ...); nullopt for a regular file or none at all.
std::optional<std::string> notRegularFile(const FileStamp& stamp);

}  // namespace ray
