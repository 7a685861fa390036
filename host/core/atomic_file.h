// Writing a file so that it is either completely there or not changed at all.
//
// Every file ray writes (images, partial images, statistics JSON; the library, the Python
// module and the viewer call the same functions) goes to a temporary file beside the
// target, in the same folder so that the final rename cannot cross file systems. Every
// write is checked, the file is fsync'd and closed (checked too: NFS and some FUSE file
// systems report a full disk only at close), and only then renamed over the target. On any
// failure the temporary file is removed, the old target is untouched, and FileWriteError
// names the path and the system's reason ("No space left on device").
#pragma once

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string_view>

namespace ray {

// A file could not be written; the message names the target and the system's reason.
struct FileWriteError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Writes the bytes to `target` atomically (see above). Throws FileWriteError.
void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes);

// For an encoder that can only write to a path: `writeTemporary` writes the whole file to
// the path it is given (beside the target, with the target's extension so a format chosen
// by extension stays the same) and throws on its own errors. That file is then fsync'd and
// renamed over the target; on any failure it is removed. Throws FileWriteError, or what
// `writeTemporary` threw.
void writeFileAtomicallyVia(const std::filesystem::path& target,
                            const std::function<void(const std::filesystem::path& temporary)>& writeTemporary);

// Creates and removes a temporary file where writeFileAtomically would, so that a folder
// ray cannot write to is found before a render, not after it. Throws FileWriteError.
void checkCanWriteBeside(const std::filesystem::path& target);

}  // namespace ray
