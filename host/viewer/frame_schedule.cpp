// The session's render thread (viewer_session.h): what to render next and rendering it.
// Each new view or scene is first rendered with one sample a pixel (a preview, quick while
// something moves; smaller than the view when the view is slow to render:
// preview_resolution.h), then, once it has rested for kRestDelay, at the view's size with
// the antialiasing asked for.
//
// A new request cancels a refinement in flight at once, but lets a preview finish: a drag
// sends a request every few milliseconds, and a preview cancelled by each would never be
// shown. A preview is kept short by its size, so the latest request waits at most about
// one preview; one that overruns kPreviewPatience (the first of a heavy scene) is given up
// all the same, and the next is made smaller.
#include <chrono>
#include <string>

#include "viewer/viewer_session.h"

namespace ray {

namespace {

// How long the view must stay unchanged before it is refined to the full antialiasing.
constexpr auto kRestDelay = std::chrono::milliseconds(350);
// A preview in flight longer than this is cancelled by a newer request.
constexpr auto kPreviewPatience = 4 * kPreviewBudget;

}  // namespace

// Called with mutex_ held.
bool Session::previewInFlightLocked() const { return frameInFlight_ && frameKind_.antialias == AntialiasMode::Off; }

// Called with mutex_ held.
void Session::newRequest() {
    ++requested_;
    lastRequestAt_ = Clock::now();
    if (!previewInFlightLocked() || lastRequestAt_ - frameStartedAt_ > kPreviewPatience) cancel_ = true;
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
            const PreviewSize preview = previewResolution_.size(view_.settings.width, view_.settings.height);
            // A preview smaller than the view is refined even without antialiasing.
            refined = refined && preview.divisor == 1;
            kind = {requested_, sceneVersion_, AntialiasMode::Off, refined, preview.divisor};
            return true;
        }
        const auto restAt = lastRequestAt_ + kRestDelay;
        if (!refined && frameDone_ && Clock::now() >= restAt) {
            refined = true;
            kind = {requested_, sceneVersion_, view_.settings.antialias, true, 1};
            return true;
        }
        if (!refined && frameDone_) changed_.wait_until(lock, restAt);
        else changed_.wait(lock);
    }
}

// Called with mutex_ held: the pixels of the frame in flight rendered so far.
double Session::pixelsRenderedLocked() const {
    double pixels = 0;
    for (const FrameTile& tile : tiles_) pixels += double(tile.width) * double(tile.height);
    return pixels;
}

// Called with mutex_ held, as the next frame starts: the frame just finished stays for the
// streams that have not sent all of it (event_stream.cpp).
void Session::keepFinishedFrameLocked() {
    if (!frameDone_) return;  // cancelled: nothing of it is worth sending any more
    finishedFrame_ = frame_;
    finishedTiles_ = std::move(tiles_);
    finishedDone_ = doneJson_;
}

// Called with mutex_ held, after a frame: a preview teaches what a pixel costs.
void Session::learnPreviewCost(bool finished, double seconds) {
    if (frameKind_.antialias != AntialiasMode::Off) return;
    if (finished) previewResolution_.rendered(double(frameWidth_) * double(frameHeight_), seconds);
    else previewResolution_.abandoned(pixelsRenderedLocked(), seconds);
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
            viewWidth_ = view.settings.width;
            viewHeight_ = view.settings.height;
            const PreviewSize rendering = dividedView(view.settings.width, view.settings.height, kind.divisor);
            view.settings.width = rendering.width;
            view.settings.height = rendering.height;
            view.settings.antialias = kind.antialias;
            cancel_ = false;
            keepFinishedFrameLocked();
            ++frame_;
            frameKind_ = kind;
            tiles_.clear();
            frameDone_ = false;
            frameInFlight_ = true;
            frameStartedAt_ = Clock::now();
            frameWidth_ = view.settings.width;
            frameHeight_ = view.settings.height;
            changed_.notify_all();
        }
        auto start = Clock::now();
        uint64_t rays = 0;
        try {
            rays = source_->renderFrame(scene, view.camera, view.settings,
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
            frameInFlight_ = false;
            sceneError_ = std::string("rendering failed: ") + e.what();
            errorIsFrames_ = true;
            refined = true;
            changed_.notify_all();
            continue;
        }
        double seconds = std::chrono::duration<double>(Clock::now() - start).count();
        std::lock_guard lock(mutex_);
        frameInFlight_ = false;
        learnPreviewCost(!cancel_, seconds);
        if (cancel_) continue;
        if (errorIsFrames_) {  // a frame rendered again: the failure shown is over
            sceneError_.clear();
            errorIsFrames_ = false;
        }
        frameDone_ = true;
        doneJson_ = {{"frame", frame_}, {"seconds", seconds}, {"rays", rays},
                     {"mrays", seconds > 0 ? double(rays) / seconds / 1e6 : 0.0}, {"device", source_->deviceName()}};
        doneJson_.update(frameKindJson(kind));
        changed_.notify_all();
    }
}

}  // namespace ray
