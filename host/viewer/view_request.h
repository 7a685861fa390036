// What the page asks to see and is told about it: a view (the camera and the render
// settings within the viewer's limits), parsed from POST /view and checked whole; the view
// as /state reports it; the controls the page builds from the settings table (GET
// /settings); and what a frame shows (its view, scene and antialiasing), as the event
// stream names it.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "render/render_settings.h"
#include "scene/scene.h"

namespace ray {

// The sizes and depths the viewer accepts, from its command line and from the page.
constexpr int kMinViewSide = 8;
constexpr int kMaxViewSide = 2048;
constexpr int kMaxViewDepth = 16;

struct View {
    Camera camera;
    RenderSettings settings;
};

// `current` changed by a view request from the page (camera and settings, any subset).
// Throws std::invalid_argument or nlohmann::json::exception on anything malformed or out
// of range, changing nothing.
View parseView(const std::string& body, const View& current);

// The view as /state reports it: position, look, up, height_angle (the file's, which a view
// request does not change), width, height, depth, dof and every other setting by its table
// name.
nlohmann::json viewJson(const View& view);

// What the page builds its setting controls from: every setting of the table but those it
// lays out itself (size, depth, depth of field), with its kind, default, range or choices
// and help.
nlohmann::json settingControlsJson();

// What a frame is: the view (request number) and scene (reload number) it shows, and
// whether it is the quick preview of a change or the view at rest, refined.
struct FrameKind {
    uint64_t view = 0, scene = 0;
    AntialiasMode antialias = AntialiasMode::Off;
    bool final = true;  // no refinement follows
    int divisor = 1;    // a preview may be rendered at the view's size over this (preview_resolution.h)
};

nlohmann::json frameKindJson(const FrameKind& kind);

// The text of every JSON answer and event the page is sent. Paths and the messages that
// quote them may hold bytes that are not UTF-8 (a folder named in another encoding), which
// JSON cannot carry: each such byte is written as U+FFFD, here alone, so that no answer fails
// on them (a /state that answered 500, an edit applied and answered 400).
std::string jsonText(const nlohmann::json& value);

}  // namespace ray
