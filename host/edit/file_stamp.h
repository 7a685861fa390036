// What a scene file was when it was read or written: its size and a hash of its bytes (its
// modification time says nothing a save needs: touched, its bytes are the same, and two
// writes within the clock's step leave it as it was). A save compares the file on disk with it, and does not replace a file
// that another program changed since (docs/modeler-protocol.md, POST /save; the C++ API's
// and Python's save), unless the user says to: their change would be lost without a word.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace ray::edit {

struct FileStamp {
    bool exists = false;
    bool regular = false;
    uintmax_t size = 0;
    uint64_t hash = 0;  // FNV-1a, 64 bits, of the bytes
};

// The file as it is now (not there: exists false). Reads it whole to hash it.
FileStamp stampOf(const std::filesystem::path& file);

// Why `file` on disk is not what `then` recorded, as a phrase ("was changed on disk (3 bytes
// longer)"); nullopt when its bytes are the same (a new modification time alone is no
// change) or it was removed (a save then replaces nothing).
std::optional<std::string> changeSince(const FileStamp& then, const std::filesystem::path& file);

}  // namespace ray::edit
