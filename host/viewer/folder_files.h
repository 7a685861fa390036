// The files a viewer request may name: files directly in the scene's folder, by name.
//
// The page is trusted to ask, not to choose where ray writes: a name from a request ("save
// as other.xml") is checked here before it becomes a path. It must be a plain file name in
// the scene's folder (or an absolute path to one there): no folder of its own, no "..", no
// NUL or control character, of a sane length, with the extension the operation takes.
// Writing then follows no link and replaces no existing file unless the request says so
// (the page asks the user first). What this does not stop: another program of the same
// user that swaps the folder's contents between the check and the write; it could write
// there itself.
#pragma once

#include <filesystem>
#include <initializer_list>
#include <stdexcept>
#include <string_view>

namespace ray {

// A name that is not a file of the folder (the message says why and what to give instead).
struct BadFileName : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

// The file exists and the request did not say to replace it.
struct FileExists : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// `name` as a path directly inside `folder`, whose extension (in any case) is one of
// `extensions` (".xml"). `what` names the operation in messages ("save as"). Throws
// BadFileName.
std::filesystem::path fileInFolder(const std::filesystem::path& folder, std::string_view name, std::string_view what,
                                   std::initializer_list<std::string_view> extensions);

// Checks that `file` (from fileInFolder) may be written: not a link, not a folder or a
// device, and, unless `replace`, not there at all. Throws BadFileName or FileExists.
void checkMayWrite(const std::filesystem::path& file, bool replace, std::string_view what);

}  // namespace ray
