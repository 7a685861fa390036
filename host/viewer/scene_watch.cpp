// The session's watch thread (viewer_session.h): the scene file saved by another program is
// loaded again (the edits' history starts again); a texture or mesh the scene uses, changed
// on disk, is read again and the scene shown with it (the edits kept); a broken save keeps
// the last good scene and shows why. The viewer's own saves are not taken for such a change
// (Session::edit records the stamp they leave).
//
// Every file is looked at (stat) and read without the session's lock, which is taken only to
// compare and to put in what was read: a file that blocks its reader (a FIFO put in the
// scene's place) or one slow to read never keeps the viewer from answering its page. A file
// that is not a regular file is not opened at all: the page says what it is.
#include <chrono>
#include <optional>
#include <string>

#include "core/message_text.h"
#include "image/image.h"
#include "scene/mesh.h"
#include "scene/scene_loader.h"
#include "viewer/viewer_session.h"

namespace ray {

namespace fs = std::filesystem;

namespace {

constexpr auto kWatchInterval = std::chrono::milliseconds(300);

// A scene file read and flattened, its images and meshes loaded: all the reading a reload does.
struct SceneRead {
    edit::FileStamp content;  // taken before it is read: a save compares the file with it
    SceneDocument document;
    Resources resources;
};

SceneRead readScene(const fs::path& file, const LoadOptions& options) {
    edit::FileStamp content = edit::stampOf(file);
    SceneRead read{content, loadSceneDocument(file, options), {}};
    flattenDocument(read.document, read.resources, options);
    return read;
}

// `file`, one of `resources`' images or meshes, read again into its place. Throws.
void readAgain(Resources& resources, const fs::path& file, const FileStamp& stamp) {
    if (!stamp.exists) throw std::runtime_error("cannot find " + quotedForMessage(file.string()));
    if (std::optional<std::string> why = notRegularFile(stamp))
        throw std::runtime_error(quotedForMessage(file.string()) + " " + *why);
    if (auto image = resources.imageIndex.find(file); image != resources.imageIndex.end()) {
        Image fresh = readImage(file);
        if (image->second < 0) {  // unreadable when the scene was loaded: readable now
            image->second = int(resources.images.size());
            resources.images.push_back(std::move(fresh));
            resources.imageFiles.push_back(file);
        } else {
            resources.images[size_t(image->second)] = std::move(fresh);
        }
    }
    if (auto mesh = resources.meshIndex.find(file); mesh != resources.meshIndex.end() && mesh->second >= 0)
        resources.meshes[size_t(mesh->second)] = loadObjMesh(file);
}

}  // namespace

std::vector<fs::path> Session::resourceFilesLocked() const {
    std::vector<fs::path> files;
    const Resources& resources = editor_.resources();
    for (const auto* index : {&resources.imageIndex, &resources.meshIndex})
        for (const auto& [file, at] : *index) files.push_back(file);
    return files;
}

void Session::watchLoop() {
    for (;;) {
        std::vector<fs::path> files;
        std::map<fs::path, FileStamp> stamps;
        FileStamp sceneStamp;
        uint64_t saves = 0;
        {
            std::unique_lock lock(mutex_);
            if (changed_.wait_for(lock, kWatchInterval, [&] { return stop_; })) return;
            files = resourceFilesLocked();
            stamps = fileStamps_;
            sceneStamp = sceneStamp_;
            saves = saves_;
        }
        const FileStamp scene = stampOf(options_.scene);
        if (scene != sceneStamp) {
            reloadScene(scene, saves);
            continue;
        }
        std::map<fs::path, FileStamp> now;
        for (const fs::path& file : files) now[file] = stampOf(file);
        readChangedFiles(now);
    }
}

// The scene file changed (stamp): read again outside the lock, then put in.
void Session::reloadScene(const FileStamp& stamp, uint64_t saves) {
    const std::string name = options_.scene.filename().string();
    if (std::optional<std::string> why = notRegularFile(stamp)) {
        showFileError(quotedForMessage(name) + " " + *why + ": ray view reads scenes from regular files (" +
                          quotedForMessage(name) + " not reloaded: the last good version stays)",
                      stamp, saves);
        return;
    }
    try {
        SceneRead read = readScene(options_.scene, options_.load);
        std::map<fs::path, FileStamp> stamps;
        for (const auto* index : {&read.resources.imageIndex, &read.resources.meshIndex})
            for (const auto& [file, at] : *index) stamps[file] = stampOf(file);
        std::lock_guard lock(mutex_);
        if (saves != saves_) return;  // the viewer saved meanwhile: the next look compares again
        // Unsaved edits the reload replaces are kept (viewer/recovery.h): the next viewer of
        // the scene offers them.
        std::optional<std::string> setAside;
        if (keeper_ && edited_ && editor_.modified()) setAside = editor_.documentText();
        editor_.reload(std::move(read.document), std::move(read.resources), read.content);
        edited_ = false;
        sceneStamp_ = stamp;
        fileStamps_ = std::move(stamps);
        log("reloaded " + name + (editor_.canUndo() ? "" : " (the edits' history starts again)"));
        if (setAside)
            log("the unsaved edits it replaced are kept in " +
                quotedForMessage(keeper_->setAside(std::move(*setAside)).string()) + ": ray view " +
                options_.scene.string() + " --recover opens them");
        if (keeper_) keeper_->sceneRead();
        scene_ = editor_.scene();
        sceneError_.clear();
        filesError_.clear();
        errorIsFrames_ = false;
        ++sceneVersion_;
        newRequest();
    } catch (const std::exception& e) {
        showFileError(std::string(e.what()) + " (" + quotedForMessage(name) + " not reloaded: the last good version stays)",
                      stamp, saves);
    }
}

// The scene file cannot be read as it is now: the page and the terminal say why, and it is
// not read again until it changes.
void Session::showFileError(const std::string& message, const FileStamp& stamp, uint64_t saves) {
    log(message);
    std::lock_guard lock(mutex_);
    if (saves != saves_) return;
    sceneStamp_ = stamp;
    sceneError_ = message;
    errorIsFrames_ = false;
    changed_.notify_all();
}

// Textures and meshes whose stamps differ from those last read are read again (outside the
// lock) and the scene flattened with them; one the scene started using since the last look
// is stamped.
void Session::readChangedFiles(const std::map<fs::path, FileStamp>& now) {
    std::map<fs::path, FileStamp> changed;
    Resources resources;
    uint64_t version = 0;
    {
        std::lock_guard lock(mutex_);
        for (const auto& [file, stamp] : now) {
            auto known = fileStamps_.find(file);
            if (known == fileStamps_.end()) fileStamps_.emplace(file, stamp);
            else if (known->second != stamp) changed.emplace(file, stamp);
        }
        if (changed.empty()) return;
        resources = editor_.resources();
        version = editor_.version();
    }
    std::string problems;
    for (const auto& [file, stamp] : changed) {
        try {
            readAgain(resources, file, stamp);
        } catch (const std::exception& e) {
            problems += (problems.empty() ? "" : "\n") + std::string(e.what()) + " (not read again: the last good version stays)";
        }
    }
    std::lock_guard lock(mutex_);
    if (editor_.version() != version) return;  // an edit came between: the next look reads them again
    for (const auto& [file, stamp] : changed) fileStamps_[file] = stamp;
    try {
        editor_.refreshResources(std::move(resources));
    } catch (const std::exception& e) {
        problems += (problems.empty() ? "" : "\n") + std::string(e.what());
    }
    for (const auto& [file, stamp] : changed) log("read again " + quotedForMessage(file.filename().string()));
    if (!problems.empty()) log(problems);
    scene_ = editor_.scene();
    // The page shows what could not be read; a message of an earlier look goes once all are
    // read (a broken scene file's stays).
    if (!problems.empty() || sceneError_ == filesError_) {
        sceneError_ = problems;
        filesError_ = problems;
        errorIsFrames_ = false;
    }
    ++sceneVersion_;
    newRequest();
}

}  // namespace ray
