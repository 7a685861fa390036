// What the viewer's server threads share: the scene being edited, the view, the frame being
// rendered and its tiles, under one mutex. Its jobs are each a file of their own:
//   viewer_session.cpp  the requests: the state, a new view, picks, edits, saves, explanations
//   frame_schedule.cpp  the render thread: the latest request's preview (smaller than the
//                       view when the view is slow to render), then its refinement once the
//                       view rests; a new request cancels a refinement in flight, and lets
//                       a preview finish
//   scene_watch.cpp     the watch thread: the scene file changed on disk is loaded again, a
//                       texture or mesh it uses read again; files are read outside the lock
//   event_stream.cpp    the /events stream: frames, tiles and scene changes as they happen
// The routes (viewer_routes.h) call it; runViewer (viewer_server.h) starts and stops it.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/frame_source.h"
#include "viewer/file_stamp.h"
#include "viewer/preview_resolution.h"
#include "viewer/recovery.h"
#include "viewer/scene_editor.h"
#include "viewer/view_request.h"
#include "viewer/viewer_server.h"

namespace httplib {
class DataSink;
}

namespace ray {

class Session {
public:
    Session(const ViewerOptions& options, std::unique_ptr<FrameSource> source);

    // Starts the render and watch threads; stop() ends and joins them.
    void start();
    void stop();

    // GET /state: the scene, the device, the view, the editor's state, errors and versions.
    nlohmann::json state();
    // POST /view: a new view; the frame in flight is cancelled, the latest alone rendered.
    // Returns its number, which the frames that show it carry (FrameKind::view).
    uint64_t request(const std::string& body);
    // GET /pick: what pixel (x, y) of the current view shows (SceneEditor::pick).
    nlohmann::json pick(int x, int y);
    // GET /object: an object's description (SceneEditor::objectJson).
    nlohmann::json object(int id);
    // GET /outline, GET /node (docs/modeler-protocol.md).
    nlohmann::json outline();
    nlohmann::json node(const std::string& id);
    // POST /op, /edit, /undo, /redo, /save: what it changed and the editor's state after it
    // ("editor", and at the top level for the page of today), and the edited object for
    // /edit. A change to the scene re-renders the view, preview first. Throws EditError
    // (a body that is not JSON too), BadFileName, FileExists.
    nlohmann::json edit(const std::string& action, const std::string& body);
    // GET /recovery: {"offer": the newest recovery of the scene (viewer/recovery.h) another
    // viewer left, or null}. POST /recovery {"action": "restore" | "discard", "file": the
    // offer's}: its edits opened as unsaved changes (refused while this viewer has edits of
    // its own), or its file removed; the next offer, and the editor's state. Throws EditError.
    nlohmann::json recoveryOffer();
    nlohmann::json answerRecovery(const std::string& body);
    // POST /reload (viewer_session.cpp): the file read again, outside the lock.
    nlohmann::json reloadOnRequest(const std::string& body);
    // GET /explain: pixel (x, y)'s tree of rays, naming the view and scene it was made for,
    // so that the page can tell when a later frame has made it stale.
    nlohmann::json explain(int x, int y);

    // What one /events client has been sent so far.
    struct Cursor {
        uint64_t id = 0;  // the order the stream was opened in
        uint64_t frame = 0;
        size_t sent = 0;
        bool doneSent = false;
        std::string error;
        uint64_t sceneVersion = 0;
    };
    // A new /events client's place in the order of streams.
    uint64_t openStream();
    // Writes, as server-sent events, what happened since `cursor`; waits up to a second.
    // False when the stream is to end (the server stops, or newer streams displaced it).
    bool stream(httplib::DataSink& sink, Cursor& cursor);

private:
    using Clock = std::chrono::steady_clock;

    // The editor's part of the state. Called with mutex_ held.
    nlohmann::json editorStateLocked();
    // The document's text while it has unsaved edits made here (the recovery keeper's
    // snapshot); nullopt without. Takes mutex_.
    std::optional<std::string> unsavedDocument();
    // The document changed (or was saved: `now`): its recovery copy follows. mutex_ held.
    void documentChangedLocked(bool now);
    // The offer after `answered`: the newest other recovery of the scene. Reads the folder.
    std::optional<Recovery> nextOffer(const std::filesystem::path& answered) const;
    nlohmann::json restoreRecovery(const std::filesystem::path& file);
    nlohmann::json discardRecovery(const std::filesystem::path& file);
    void log(const std::string& message) const;

    // frame_schedule.cpp
    void newRequest();
    bool nextFrame(std::unique_lock<std::mutex>& lock, uint64_t& rendered, bool& refined, FrameKind& kind);
    void renderLoop();
    bool previewInFlightLocked() const;
    double pixelsRenderedLocked() const;
    void learnPreviewCost(bool finished, double seconds);
    void keepFinishedFrameLocked();

    // scene_watch.cpp
    void watchLoop();
    void reloadScene(const FileStamp& stamp, uint64_t saves);
    void readChangedFiles(const std::map<std::filesystem::path, FileStamp>& stamps);
    void showFileError(const std::string& message, const FileStamp& stamp, uint64_t saves);
    std::vector<std::filesystem::path> resourceFilesLocked() const;

    const ViewerOptions& options_;
    std::unique_ptr<FrameSource> source_;
    SceneEditor editor_;  // the document, its edits and history, under mutex_
    std::mutex mutex_;
    std::condition_variable changed_;
    std::shared_ptr<const Scene> scene_;
    FileStamp sceneStamp_;  // the scene file as last read or saved
    // The textures and meshes the scene uses as last read (scene_watch.cpp); files an edit
    // named since are stamped by the next look.
    std::map<std::filesystem::path, FileStamp> fileStamps_;
    std::string filesError_;  // the textures' and meshes' that could not be read again, shown in sceneError_
    uint64_t saves_ = 0;  // the editor's own saves: a look at the file that raced one is made again
    std::string sceneError_;      // shown in the page: a broken save, or a failed frame
    bool errorIsFrames_ = false;  // sceneError_ is a failed frame's
    View view_;
    uint64_t requested_ = 0;     // view requests so far: the id of the latest view
    uint64_t sceneVersion_ = 0;  // successful reloads so far
    Clock::time_point lastRequestAt_ = Clock::now();
    FrameKind frameKind_;  // what the frame frame_ shows
    Clock::time_point frameStartedAt_ = Clock::now();
    bool frameInFlight_ = false;
    PreviewResolution previewResolution_;
    std::atomic<bool> cancel_{false};
    bool stop_ = false;
    uint64_t frame_ = 0;
    int frameWidth_ = 0, frameHeight_ = 0;  // what the frame renders: a preview may be smaller
    int viewWidth_ = 0, viewHeight_ = 0;    // the view it is shown in
    uint64_t streamsOpened_ = 0;
    std::vector<FrameTile> tiles_;  // the current frame's
    bool frameDone_ = false;
    nlohmann::json doneJson_;
    // The last complete frame once the next has started: a stream that had not sent all of
    // it yet sends the rest and its "done" first (the render thread starts the next preview
    // at once while something moves). Memory stays two frames.
    uint64_t finishedFrame_ = 0;
    std::vector<FrameTile> finishedTiles_;
    nlohmann::json finishedDone_;
    std::thread renderThread_, watchThread_;
    // Unsaved edits (viewer/recovery.h): whether the document holds edits made in this viewer
    // (a new scene's camera and light are none), the keeper of their copy, the recovery
    // offered to the page (its document not held).
    bool edited_ = false;
    std::unique_ptr<RecoveryKeeper> keeper_;
    std::optional<Recovery> offer_;
};

}  // namespace ray
