#include "edit/file_stamp.h"

#include <fstream>
#include <vector>

#include "core/fnv1a.h"

namespace ray::edit {

namespace {

// The FNV-1a hash of the file's bytes; nullopt when it cannot be read.
std::optional<uint64_t> hashOf(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) return std::nullopt;
    Fnv1a hash;
    std::vector<char> buffer(size_t(1) << 16);
    while (in) {
        in.read(buffer.data(), std::streamsize(buffer.size()));
        hash.add(buffer.data(), size_t(in.gcount()));
    }
    if (in.bad()) return std::nullopt;
    return hash.value();
}

}  // namespace

FileStamp stampOf(const std::filesystem::path& file) {
    FileStamp stamp;
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(file, ec);
    stamp.exists = std::filesystem::exists(status);
    stamp.regular = std::filesystem::is_regular_file(status);
    if (!stamp.regular) return stamp;  // a FIFO is never read here: it could block
    stamp.size = std::filesystem::file_size(file, ec);
    stamp.hash = hashOf(file).value_or(0);
    return stamp;
}

std::optional<std::string> changeSince(const FileStamp& then, const std::filesystem::path& file) {
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(file, ec);
    if (!std::filesystem::exists(status)) return std::nullopt;
    if (!then.exists) return "was made on disk by another program after this scene was opened";
    if (!std::filesystem::is_regular_file(status)) return "was replaced on disk by something that is not a regular file";
    const uintmax_t size = std::filesystem::file_size(file, ec);
    if (ec) return "cannot be read to compare (" + ec.message() + ")";
    if (size != then.size)
        return "was changed on disk by another program (now " + std::to_string(size) + " bytes, " +
               std::to_string(then.size) + " when this scene read or wrote it)";
    const std::optional<uint64_t> hash = hashOf(file);
    if (!hash) return "cannot be read to compare";
    if (*hash != then.hash) return "was changed on disk by another program (the same size, other bytes)";
    return std::nullopt;
}

}  // namespace ray::edit
