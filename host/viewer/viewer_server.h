// `ray view`: an HTTP server in the process serving one page of its own (web/index.html
// with its modules and three.js bundled in, embedded at build time: viewer_page.h), the frame tile by tile as server-sent events, camera and
// settings changes, the scene file watched, "explain this pixel", and the modeler: the
// object under a click (/pick, /object), edits of its material and transform and of the
// lights, undo, redo and saving (POST /edit, /undo, /redo, /save: viewer/scene_editor.h).
//
// Only these routes exist (/, /settings, /state, /view, /events, /explain, /pick, /object,
// /edit, /undo, /redo, /save, /recovery); nothing is ever read from disk for a request but
// the recovery offered (viewer/recovery.h), and only /save writes a file: the scenefile, or
// a .xml file the user names in its folder (viewer/folder_files.h). The editing routes answer 403 in a viewer without a token
// (--no-token): only the viewer's user may change the scene or its file. Every request
// passes viewer/request_guard.h first: the viewer's own page or a script with the access
// token, nothing else (403). Request bodies are capped, every number is range-checked, and
// each change cancels the frame in flight: the renderer works on the latest request only.
//
// The page builds its setting controls from /settings, which the server makes from the
// settings table (render/settings_table.h): every render setting but the size, depth and
// depth of field, which the page lays out itself.
//
// Frames: a change is first rendered with one sample a pixel (quick, while the camera
// moves; smaller than the view when the view is slow: preview_resolution.h); once the view
// has rested for a moment it is rendered again at its size with the antialiasing asked for
// (the CLI's default, the course's), the image `ray scene W H` makes.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "edit/edit_session.h"
#include "render/frame_source.h"
#include "scene/scene_loader.h"
#include "viewer/recovery.h"
#include "viewer/view_request.h"

namespace ray {

// The port is taken (another `ray view`, or any other server): binding fails rather than
// sharing it (cpp-httplib's default sets SO_REUSEPORT, which let two viewers both listen).
struct AddressInUse : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct ViewerOptions {
    std::filesystem::path scene;
    std::string address = "127.0.0.1";
    int port = 8123;  // 0: any free port
    RenderSettings settings;  // antialias: what a view at rest is refined to
    // The page sizes the view to its window; false: it keeps settings' width and height
    // (given on the command line) until the user chooses another size.
    bool fitWindow = true;
    // The scene file does not exist: the viewer opens a new scene (viewer/new_scene.h) and
    // writes it there on the first save.
    bool newScene = false;
    LoadOptions load;
    // The most memory the undo history holds (ray view --undo-memory; edit::SessionOptions).
    size_t historyLimit = edit::SessionOptions::kDefaultHistoryLimit;
    // The access token every request must present; empty: the viewer is open (--no-token).
    std::string token;
    // Unsaved edits are kept in this folder (viewer/recovery.h); empty: not kept.
    std::filesystem::path recoveryFolder;
    // --recover: the scene opens with this recovery's edits, as unsaved changes.
    std::optional<Recovery> recovered;
    // The newest recovery of the scene, offered by the page (Restore, Discard).
    std::optional<Recovery> offer;
    // Stopped by SIGINT, SIGTERM or SIGHUP (viewer/stop_signals.h, made by the caller):
    // told the signal and what became of the unsaved edits, before the process exits.
    std::function<void(int signal, const RecoveryKeeper::Kept& kept)> onStopSignal;
    // --frame-ancestors: the pages that may show the viewer in a frame (request_guard.h).
    std::string frameAncestors;
    // Called once the server listens, with the port it got.
    std::function<void(int port)> onListening;
    // The terminal's log: reloads, broken saves, failed frames (never the token).
    std::function<void(const std::string& message)> log;
};

// Serves until the process is stopped. Throws InputError for a scene that does not load at
// start and AddressInUse / std::runtime_error when the address cannot be bound.
void runViewer(const ViewerOptions& options, std::unique_ptr<FrameSource> source);

}  // namespace ray
