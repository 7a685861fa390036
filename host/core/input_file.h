// The one way ray opens a file it reads besides the scene itself: textures and bump maps,
// meshes (OBJ), an OBJ's material library, recovery files. Every such file is named by
// someone else (a scene, an OBJ, the API's caller), so before a byte is read it must be a
// regular file (after symbolic links) of a size its kind can justify: a FIFO would hang the
// reader, /dev/zero would never end, a 4 GB file named as a material library would be held
// in memory whole. A check takes a stat and, for reading, an open that cannot block (a FIFO
// is opened without waiting for a writer, then refused), so a refusal comes at once.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace ray {

// What kind of file is read, and the most bytes that kind can need. Each reader declares
// its own next to its decoder (image/image_io.cpp, scene/mesh.cpp).
struct InputLimit {
    const char* what;   // "an image", "a mesh (OBJ)": the message's name for the file
    uint64_t maxBytes;  // larger files are refused before they are read
    const char* why;    // what the limit stands for, for the message ("2^25 pixels of floats")
    // A symbolic link at the path itself is refused, not followed (a file ray wrote itself in
    // a private folder, such as a recovery copy, is never a link).
    bool refuseLink = false;
};

// A file refused or unreadable. what() is "<file>: <reason>; <what to do>"; reason() is the
// part after the file, for callers that format their own place ("file: error: ...").
class InputFileError : public std::runtime_error {
public:
    InputFileError(const std::filesystem::path& file, const std::string& reason)
        : std::runtime_error(file.string() + ": " + reason), reason_(reason) {}
    const std::string& reason() const { return reason_; }

private:
    std::string reason_;
};

// For decoders that open the file by its path: the file is a regular file of at most
// limit.maxBytes. Returns its size. Throws InputFileError.
uint64_t checkInputFile(const std::filesystem::path& file, const InputLimit& limit);

// The whole file, read through the descriptor that was checked (so that no other file can
// be swapped in between the check and the read). Throws InputFileError.
std::string readInputFile(const std::filesystem::path& file, const InputLimit& limit);

}  // namespace ray
