// The session's watch thread (viewer_session.h): the scene file saved by another program is
// loaded again (the edits' history starts again); a broken save keeps the last good scene
// and shows why. The viewer's own saves are not taken for such a change (Session::edit
// records the time they leave).
#include <chrono>
#include <optional>
#include <string>

#include "core/message_text.h"
#include "viewer/viewer_session.h"

namespace ray {

namespace {

constexpr auto kWatchInterval = std::chrono::milliseconds(300);

}  // namespace

std::filesystem::file_time_type Session::lastWrite() const {
    std::error_code ec;
    return std::filesystem::last_write_time(options_.scene, ec);
}

void Session::watchLoop() {
    for (;;) {
        {
            std::unique_lock lock(mutex_);
            if (changed_.wait_for(lock, kWatchInterval, [&] { return stop_; })) return;
        }
        const auto time = lastWrite();
        {
            std::lock_guard lock(mutex_);  // the editor's saves set it too
            if (time == sceneTime_) continue;
            sceneTime_ = time;
        }
        const std::string name = options_.scene.filename().string();
        try {
            std::lock_guard lock(mutex_);
            // Unsaved edits the reload replaces are kept (viewer/recovery.h): the next
            // viewer of the scene offers them.
            std::optional<std::string> setAside;
            if (keeper_ && edited_ && editor_.modified()) setAside = editor_.documentText();
            editor_.reload();
            edited_ = false;
            log("reloaded " + name + (editor_.canUndo() ? "" : " (the edits' history starts again)"));
            if (setAside)
                log("the unsaved edits it replaced are kept in " +
                    quotedForMessage(keeper_->setAside(std::move(*setAside)).string()) + ": ray view " +
                    options_.scene.string() + " --recover opens them");
            if (keeper_) keeper_->sceneRead();
            scene_ = editor_.scene();
            sceneError_.clear();
            errorIsFrames_ = false;
            ++sceneVersion_;
            newRequest();
        } catch (const std::exception& e) {
            log(std::string(e.what()) + " (" + name + " not reloaded: the last good version stays)");
            std::lock_guard lock(mutex_);
            sceneError_ = e.what();
            errorIsFrames_ = false;
            changed_.notify_all();
        }
    }
}

}  // namespace ray
