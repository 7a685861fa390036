// The one writer of every file ray writes: images, partial images, statistics and explain
// JSON, scenes (the library, the Python module and the viewer call the same functions), the
// kernel cache and recovery files. Call writeFileAtomically (bytes in memory) or
// writeFileAtomicallyVia (an encoder that writes to a path); call checkCanWrite before the
// work that produces the bytes, so that a refusal comes before a render, not after it.
//
// What the target is decides how it is written, as a user who named it expects:
// - a regular file, or no file yet: the bytes go to a temporary file beside it (the same
//   folder, so the rename cannot cross file systems), every write checked, fsync'd and closed
//   (checked too: NFS and some FUSE file systems report a full disk only at close), and only
//   then renamed over it. The old file keeps its mode and, where the system allows (root, or
//   a group the user is in), its owner and group. On any failure the temporary file is
//   removed and the old file is untouched.
//   A file with other hard links is replaced like any other: its other names keep the old
//   bytes (a write in place could leave every name half written), and a warning names the
//   file and how many names it had, so the user knows those copies went stale.
//   A read-only file (no write permission for the user; for root, no owner write bit) is
//   refused unless WriteOptions::replaceReadOnly says to replace it: its mode asked for it
//   to be kept as it is.
// - a symbolic link: followed to its final target, which is written as above (the temporary
//   file beside the target, not beside the link), so the link stays a link.
// - a character device, a FIFO, or one of the process's own descriptors (/dev/stdout,
//   /dev/stderr, /dev/fd/N, /proc/self/fd/N): written into, never replaced. A FIFO no
//   program opens for reading within kFifoReaderWait is refused rather than waited for.
// - a folder, a block device, a socket: refused with a sentence (OutputRefused).
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace ray {

// A file could not be written (the system failed: a full disk, no permission); the message
// names the target and the system's reason. The command line exits 3.
struct FileWriteError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The target is something ray will not write as asked: a folder, a block device, a socket,
// a read-only file, the input it is reading. Bad input: the command line exits 2. The
// message names the path and says what to do.
struct OutputRefused : FileWriteError {
    using FileWriteError::FileWriteError;
};

struct WriteOptions {
    // Replace a read-only file (ray --replace-read-only; the API's replaceReadOnly).
    bool replaceReadOnly = false;
    // How the user says replaceReadOnly where they are, for the refusal's sentence.
    std::string replaceReadOnlyHint = "--replace-read-only";
    // Notes that are no failure (a hard link's other names keep the old bytes). Empty: each
    // goes to stderr as "ray: warning: ...".
    std::function<void(const std::string&)> warn;
};

// How long a write into a FIFO waits for a program to open it for reading.
constexpr std::chrono::seconds kFifoReaderWait{10};

// Writes the bytes to `target` as described above. Throws OutputRefused, FileWriteError.
void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes,
                         const WriteOptions& options = {});

// For an encoder that can only write to a path: `writeTemporary` writes the whole file to
// the path it is given (a temporary file with the target's extension, so a format chosen by
// extension stays the same) and throws on its own errors. That file then goes to the target
// as writeFileAtomically's bytes would: renamed over a regular file, copied into a stream.
// Throws OutputRefused, FileWriteError, or what `writeTemporary` threw.
void writeFileAtomicallyVia(const std::filesystem::path& target,
                            const std::function<void(const std::filesystem::path& temporary)>& writeTemporary,
                            const WriteOptions& options = {});

// Everything writeFileAtomically would refuse, found now: a folder, a block device, a socket,
// a read-only file, a folder that does not exist or cannot be written (a temporary file is
// created and removed where the write would make one). Opens no FIFO or device (that would
// end a reader's input). Throws OutputRefused, FileWriteError.
void checkCanWrite(const std::filesystem::path& target, const WriteOptions& options = {});

// Refuses an output that is the same file as an input (after links: the same device and
// inode), before anything is written: `ray s.xml --stats-json s.xml` must not replace the
// scene with JSON. `option` names the output as the user gave it ("--stats-json"); `what`
// names the input ("the scene"). Throws OutputRefused.
void refuseWritingOverInput(const std::filesystem::path& output, const std::string& option,
                            const std::filesystem::path& input, const std::string& what);

}  // namespace ray
