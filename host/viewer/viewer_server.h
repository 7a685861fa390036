// `ray view`: an HTTP server in the process serving one page of its own (web/index.html,
// embedded at build time), the frame tile by tile as server-sent events, camera and
// settings changes, the scene file watched, and "explain this pixel".
//
// Only five routes exist (/, /state, /view, /events, /explain); nothing is ever read from
// disk for a request, so no path can reach a file. Request bodies are capped, every number
// is range-checked, and each change cancels the frame in flight: the renderer works on the
// latest request only.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "scene/scene_loader.h"
#include "viewer/frame_source.h"

namespace ray {

// The sizes and depths the viewer accepts, from its command line and from the page.
constexpr int kMinViewSide = 8;
constexpr int kMaxViewSide = 2048;
constexpr int kMaxViewDepth = 16;

struct ViewerOptions {
    std::filesystem::path scene;
    std::string address = "127.0.0.1";
    int port = 8123;  // 0: any free port
    RenderSettings settings;
    LoadOptions load;
    // Called once the server listens, with the port it got.
    std::function<void(int port)> onListening;
};

// Serves until the process is stopped. Throws InputError for a scene that does not load at
// start and std::runtime_error when the address cannot be bound.
void runViewer(const ViewerOptions& options, std::unique_ptr<FrameSource> source);

}  // namespace ray
