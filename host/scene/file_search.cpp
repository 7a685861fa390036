// The file-reference search rule of SPEC §1.
//
// Scene files name their textures and meshes the way the course's machines saw them
// ("/course/cs123/data/image/board.png", "image\\board.png", "C:\\Users\\...\\earth.jpg").
// Rather than asking users to edit them, we look for the trailing parts of the path under a
// few roots, so a copy of the course's data folder anywhere near the scene is found.
#include "scene/file_search.h"

#include <cctype>
#include <cstdlib>
#include <system_error>

namespace fs = std::filesystem;

namespace ray {
namespace {

// How many ancestors of the scene folder are roots too (SPEC §1).
constexpr int kSceneFolderAncestors = 3;

bool isRegularFile(const fs::path& path) {
    std::error_code ignored;  // unreadable folders count as "not there"
    return fs::is_regular_file(path, ignored);
}

// An absolute, lexically normal folder without a trailing separator, so that
// parent_path() climbs one level.
fs::path normalFolder(const fs::path& folder) {
    std::error_code ignored;
    fs::path absolute = fs::absolute(folder.empty() ? fs::path(".") : folder, ignored);
    fs::path normal = absolute.lexically_normal();
    if (normal.filename().empty() && normal.has_parent_path() && normal != normal.root_path())
        normal = normal.parent_path();
    return normal;
}

// A reference as written in a scene, made POSIX-shaped: backslashes become slashes and a
// Windows drive ("C:") is dropped, remembering that the path was absolute on its machine.
struct Reference {
    std::string path;
    bool fromWindowsDrive = false;
};

Reference normalizeReference(const std::string& text) {
    Reference ref;
    ref.path = text;
    for (char& c : ref.path)
        if (c == '\\') c = '/';
    // Trim surrounding blanks: attribute values are sometimes written with them.
    size_t first = ref.path.find_first_not_of(" \t\r\n");
    size_t last = ref.path.find_last_not_of(" \t\r\n");
    ref.path = first == std::string::npos ? std::string() : ref.path.substr(first, last - first + 1);
    if (ref.path.size() >= 2 && std::isalpha(static_cast<unsigned char>(ref.path[0])) &&
        ref.path[1] == ':') {
        ref.path.erase(0, 2);
        ref.fromWindowsDrive = true;
    }
    return ref;
}

// The path's file and folder names, without the root, "." or anything up to a "..":
// a trailing part must never climb out of the root it is tried under.
std::vector<std::string> nameComponents(const fs::path& path) {
    std::vector<std::string> names;
    for (const fs::path& part : path.relative_path()) {
        std::string name = part.string();
        if (name.empty() || name == ".") continue;
        if (name == "..") {
            names.clear();
            continue;
        }
        names.push_back(name);
    }
    return names;
}

fs::path joinFrom(const std::vector<std::string>& names, size_t first) {
    fs::path joined;
    for (size_t i = first; i < names.size(); ++i) joined /= names[i];
    return joined;
}

}  // namespace

std::vector<fs::path> FileSearch::searchRoots() const {
    std::vector<fs::path> result;
    auto add = [&result](const fs::path& root) {
        for (const fs::path& known : result)
            if (known == root) return;
        result.push_back(root);
    };
    for (const fs::path& root : roots) add(normalFolder(root));
    fs::path folder = normalFolder(sceneFolder);
    add(folder);
    for (int i = 0; i < kSceneFolderAncestors; ++i) {
        fs::path parent = folder.parent_path();
        if (parent.empty() || parent == folder) break;  // reached the filesystem root
        folder = parent;
        add(folder);
    }
    return result;
}

std::optional<fs::path> FileSearch::resolve(const std::string& reference,
                                            std::vector<fs::path>* tried) const {
    Reference ref = normalizeReference(reference);
    if (ref.path.empty()) return std::nullopt;
    fs::path asGiven;  // stays empty for Windows paths, which cannot exist as given here
    auto attempt = [tried, &asGiven](const fs::path& candidate) {
        if (candidate == asGiven) return false;  // looked at already
        if (tried) tried->push_back(candidate);
        return isRegularFile(candidate);
    };

    fs::path given(ref.path);
    if (!ref.fromWindowsDrive) {
        fs::path candidate = given.is_absolute() ? given : normalFolder(sceneFolder) / given;
        if (attempt(candidate)) return candidate.lexically_normal();
        asGiven = candidate;
    }

    std::vector<std::string> names = nameComponents(given);
    for (const fs::path& root : searchRoots()) {
        for (size_t first = 0; first < names.size(); ++first) {
            fs::path candidate = root / joinFrom(names, first);
            if (attempt(candidate)) return candidate.lexically_normal();
        }
    }
    return std::nullopt;
}

std::vector<fs::path> searchPathsFromEnvironment() {
    std::vector<fs::path> folders;
    const char* value = std::getenv("RAY_SEARCH_PATH");
    if (!value) return folders;
    std::string list = value;
    size_t start = 0;
    while (start <= list.size()) {
        size_t end = list.find(':', start);
        if (end == std::string::npos) end = list.size();
        if (end > start) folders.emplace_back(list.substr(start, end - start));
        start = end + 1;
    }
    return folders;
}

}  // namespace ray
