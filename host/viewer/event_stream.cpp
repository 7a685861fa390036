// The session's /events stream (viewer_session.h), as server-sent events: "frame" when a
// frame starts (the size it renders, the view's size it is shown at, and its kind), "tile" for each finished tile (its 8-bit RGB in
// base64), "done" when the frame is complete (its time, rays and device), "scene" when the
// scene or its error changes. Each client keeps a cursor; a slow one skips to the current
// frame rather than buffering the ones it missed, but the frame it was being sent is
// finished first when it completed.
#include <httplib.h>

#include <string>
#include <vector>

#include "viewer/viewer_session.h"

namespace ray {

using nlohmann::json;

namespace {

// Open /events streams: a newer one closes the oldest beyond this many, so clients that
// connect and never read cannot take every server thread (each stream holds one).
constexpr uint64_t kMaxStreams = 6;

std::string base64(const std::vector<uint8_t>& bytes) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t n = uint32_t(bytes[i]) << 16;
        if (i + 1 < bytes.size()) n |= uint32_t(bytes[i + 1]) << 8;
        if (i + 2 < bytes.size()) n |= uint32_t(bytes[i + 2]);
        out += digits[(n >> 18) & 63];
        out += digits[(n >> 12) & 63];
        out += i + 1 < bytes.size() ? digits[(n >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? digits[n & 63] : '=';
    }
    return out;
}

std::string tileEvent(uint64_t frame, const FrameTile& t) {
    return "event: tile\ndata: " +
           jsonText(json{{"frame", frame}, {"x", t.x}, {"y", t.y}, {"w", t.width}, {"h", t.height}, {"rgb", base64(t.rgb)}}) +
           "\n\n";
}

}  // namespace

uint64_t Session::openStream() {
    std::lock_guard lock(mutex_);
    return ++streamsOpened_;
}

bool Session::stream(httplib::DataSink& sink, Cursor& cursor) {
    // References, not a structured binding: clang 14 (the fuzzing build) cannot capture
    // structured bindings in a lambda.
    const uint64_t id = cursor.id;
    uint64_t& frame = cursor.frame;
    size_t& sent = cursor.sent;
    bool& doneSent = cursor.doneSent;
    std::string& error = cursor.error;
    uint64_t& sceneVersion = cursor.sceneVersion;
    std::string out;
    {
        std::unique_lock lock(mutex_);
        changed_.wait_for(lock, std::chrono::seconds(1), [&] {
            return frame != frame_ || sent < tiles_.size() || error != sceneError_ ||
                   sceneVersion != sceneVersion_ || stop_ || (frameDone_ && !doneSent);
        });
        if (stop_ || id + kMaxStreams < streamsOpened_) return false;
        if (error != sceneError_ || sceneVersion != sceneVersion_) {
            error = sceneError_;
            sceneVersion = sceneVersion_;
            out += "event: scene\ndata: " + jsonText(json{{"error", error}, {"version", sceneVersion}}) + "\n\n";
        }
        if (frame != 0 && frame != frame_ && frame == finishedFrame_ && !doneSent) {
            // The frame this client was sent is complete, and the next has begun: the rest
            // of it first, so that every complete frame arrives complete.
            for (; sent < finishedTiles_.size(); ++sent) out += tileEvent(frame, finishedTiles_[sent]);
            out += "event: done\ndata: " + jsonText(finishedDone_) + "\n\n";
            doneSent = true;
        }
        if (frame != frame_) {
            frame = frame_;
            sent = 0;
            doneSent = false;
            json event{{"frame", frame_},          {"width", frameWidth_},          {"height", frameHeight_},
                       {"view_width", viewWidth_}, {"view_height", viewHeight_}};
            event.update(frameKindJson(frameKind_));
            out += "event: frame\ndata: " + jsonText(event) + "\n\n";
        }
        for (; sent < tiles_.size(); ++sent) out += tileEvent(frame_, tiles_[sent]);
        if (frameDone_ && sent == tiles_.size() && !doneSent) {
            doneSent = true;
            out += "event: done\ndata: " + jsonText(doneJson_) + "\n\n";
        }
    }
    if (out.empty()) out = ": keep-alive\n\n";  // notices a client that has gone
    return sink.write(out.data(), out.size());
}

}  // namespace ray
