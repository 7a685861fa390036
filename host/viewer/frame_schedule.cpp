// The session's render thread (viewer_session.h): what to render next and rendering it.
// Each new view or scene is first rendered with one sample a pixel (a preview, quick while
// something moves), then, once it has rested for kRestDelay, with the antialiasing asked
// for. A new request cancels the frame in flight: only the latest is ever finished.
#include <chrono>
#include <string>

#include "viewer/viewer_session.h"

namespace ray {

namespace {

// How long the view must stay unchanged before it is refined to the full antialiasing.
constexpr auto kRestDelay = std::chrono::milliseconds(350);

}  // namespace

// Called with mutex_ held.
void Session::newRequest() {
    ++requested_;
    lastRequestAt_ = Clock::now();
    cancel_ = true;
    changed_.notify_all();
}

// What to render next, waiting for it: the preview of the latest request, or its refinement
// once the view has rested for kRestDelay. False when stopping.
bool Session::nextFrame(std::unique_lock<std::mutex>& lock, uint64_t& rendered, bool& refined, FrameKind& kind) {
    for (;;) {
        if (stop_) return false;
        if (requested_ != rendered) {
            rendered = requested_;
            refined = view_.settings.antialias == AntialiasMode::Off;
            kind = {requested_, sceneVersion_, AntialiasMode::Off, refined};
            return true;
        }
        const auto restAt = lastRequestAt_ + kRestDelay;
        if (!refined && frameDone_ && Clock::now() >= restAt) {
            refined = true;
            kind = {requested_, sceneVersion_, view_.settings.antialias, true};
            return true;
        }
        if (!refined && frameDone_) changed_.wait_until(lock, restAt);
        else changed_.wait(lock);
    }
}

void Session::renderLoop() {
    uint64_t rendered = ~uint64_t(0);
    bool refined = true;
    for (;;) {
        std::shared_ptr<const Scene> scene;
        View view;
        FrameKind kind;
        {
            std::unique_lock lock(mutex_);
            if (!nextFrame(lock, rendered, refined, kind)) return;
            scene = scene_;
            view = view_;
            view.settings.antialias = kind.antialias;
            cancel_ = false;
            ++frame_;
            frameKind_ = kind;
            tiles_.clear();
            frameDone_ = false;
            frameWidth_ = view.settings.width;
            frameHeight_ = view.settings.height;
            changed_.notify_all();
        }
        auto start = Clock::now();
        RenderStats stats;
        try {
            stats = source_->renderFrame(scene, view.camera, view.settings,
                                        [&](const FrameTile& tile) {
                                            std::lock_guard lock(mutex_);
                                            tiles_.push_back(tile);
                                            changed_.notify_all();
                                        },
                                        cancel_);
        } catch (const std::exception& e) {
            // The viewer stays up: the page and the terminal say why, the next change tries
            // again.
            log(std::string("frame ") + std::to_string(frame_) + " failed: " + e.what());
            std::lock_guard lock(mutex_);
            sceneError_ = std::string("rendering failed: ") + e.what();
            errorIsFrames_ = true;
            refined = true;
            changed_.notify_all();
            continue;
        }
        double seconds = std::chrono::duration<double>(Clock::now() - start).count();
        std::lock_guard lock(mutex_);
        if (cancel_) continue;
        if (errorIsFrames_) {  // a frame rendered again: the failure shown is over
            sceneError_.clear();
            errorIsFrames_ = false;
        }
        frameDone_ = true;
        const uint64_t rays = stats.totalRays();
        doneJson_ = {{"frame", frame_}, {"seconds", seconds}, {"rays", rays},
                     {"mrays", seconds > 0 ? double(rays) / seconds / 1e6 : 0.0}, {"device", source_->deviceName()},
                     {"scene_update", {{"packing", stats.sceneUpdate.packing},
                                       {"bvh", stats.sceneUpdate.bvh},
                                       {"tables", stats.sceneUpdate.tables}}}};
        doneJson_.update(frameKindJson(kind));
        changed_.notify_all();
    }
}

}  // namespace ray
