#include "viewer/folder_files.h"

#include <algorithm>
#include <cctype>
#include <string>

#include "core/message_text.h"

namespace ray {
namespace fs = std::filesystem;

namespace {

// A file name's longest and a path's, in bytes (NAME_MAX and PATH_MAX on Linux).
constexpr size_t kMaxNameBytes = 255, kMaxPathBytes = 4096;

[[noreturn]] void refuse(std::string_view what, std::string_view name, const std::string& why) {
    throw BadFileName(std::string(what) + ": '" + quotedForMessage(name) + "' " + why);
}

bool hasControlCharacter(std::string_view text) {
    return std::any_of(text.begin(), text.end(), [](char c) {
        const auto byte = static_cast<unsigned char>(c);
        return byte < 0x20 || byte == 0x7f;
    });
}

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

std::string extensionList(std::initializer_list<std::string_view> extensions) {
    std::string list;
    for (std::string_view extension : extensions) list += (list.empty() ? "" : " or ") + std::string(extension);
    return list;
}

// The folder with links resolved, so that an absolute name is compared with what it is.
fs::path realFolder(const fs::path& folder) {
    std::error_code ec;
    fs::path real = fs::canonical(fs::absolute(folder), ec);
    return ec ? fs::absolute(folder).lexically_normal() : real;
}

}  // namespace

fs::path fileInFolder(const fs::path& folder, std::string_view name, std::string_view what,
                      std::initializer_list<std::string_view> extensions) {
    if (name.empty()) refuse(what, name, "is empty; give a file name such as other" + std::string(*extensions.begin()));
    if (hasControlCharacter(name)) refuse(what, name, "holds a control character (a NUL byte, a newline); give a plain file name");
    if (name.size() > kMaxPathBytes) refuse(what, name, "is longer than a path can be (" + std::to_string(name.size()) + " bytes)");
    const fs::path given(name), home = realFolder(folder);
    fs::path file;
    if (given.is_absolute()) {
        file = given.lexically_normal();
        if (file.parent_path() != home && file.parent_path() != fs::absolute(folder).lexically_normal())
            refuse(what, name, "is not in the scene's folder " + quotedForMessage(home.string()) +
                                   "; give a file name there (the viewer writes nowhere else)");
        file = home / file.filename();
    } else {
        if (given.has_parent_path() || name == "." || name == "..")
            refuse(what, name, "names a folder or leaves the scene's folder; give a plain file name, which is "
                               "written beside the scene");
        file = home / given;
    }
    const std::string filename = file.filename().string();
    if (filename.size() > kMaxNameBytes) refuse(what, name, "is longer than a file name can be (255 bytes)");
    const std::string extension = lowercase(file.extension().string());
    if (std::find(extensions.begin(), extensions.end(), extension) == extensions.end())
        refuse(what, name, "does not end in " + extensionList(extensions));
    return file;
}

void checkMayWrite(const fs::path& file, bool replace, std::string_view what) {
    std::error_code ec;
    const fs::file_status status = fs::symlink_status(file, ec);
    if (ec || status.type() == fs::file_type::not_found) return;  // a new file
    const std::string name = file.filename().string();
    if (fs::is_symlink(status))
        refuse(what, name, "is a link; the viewer neither writes through links nor replaces them");
    if (!fs::is_regular_file(status)) refuse(what, name, "is not a file (a folder, a device or a pipe)");
    if (!replace)
        throw FileExists(std::string(what) + ": " + quotedForMessage(name) + " already exists in the scene's folder");
}

}  // namespace ray
