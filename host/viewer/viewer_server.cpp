#include "viewer/viewer_server.h"

#include <httplib.h>
#include <netinet/in.h>
#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <charconv>
#include <chrono>
#include <condition_variable>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>

#include "explain/explanation_report.h"
#include "render/settings_table.h"
#include "core/message_text.h"
#include "viewer/folder_files.h"
#include "viewer/request_guard.h"
#include "viewer/scene_editor.h"
#include "viewer/viewer_page.h"

namespace ray {

namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

// Bounds on what a client may ask for: a frame is at most 2048² (12 MiB of 8-bit RGB).
constexpr size_t kMaxRequestBody = 16 * 1024;
constexpr auto kWatchInterval = std::chrono::milliseconds(300);
// Open /events streams: a newer one closes the oldest beyond this many, so clients that
// connect and never read cannot take every server thread (each stream holds one).
constexpr uint64_t kMaxStreams = 6;
constexpr size_t kServerThreads = 24;
// How long the view must stay unchanged before it is refined to the full antialiasing.
constexpr auto kRestDelay = std::chrono::milliseconds(350);

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

Vec3 vec3From(const json& j) {
    if (!j.is_array() || j.size() != 3) throw std::invalid_argument("a vector must be [x, y, z]");
    Vec3 v{j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) || length(v) > 1e9)
        throw std::invalid_argument("vector out of range");
    return v;
}

int intIn(const json& j, const char* key, int lo, int hi, int fallback) {
    if (!j.contains(key)) return fallback;
    int v = j.at(key).get<int>();
    if (v < lo || v > hi) throw std::invalid_argument(std::string(key) + " out of range");
    return v;
}

json vecJson(const Vec3& v) { return json::array({v.x, v.y, v.z}); }

struct View {
    Camera camera;
    RenderSettings settings;
};

// The viewer lays out these table entries itself: the size and depth within its own
// limits, and depth of field as one control, "dof": off, or --dof's course | disk.
bool viewerOwnControl(std::string_view name) {
    return name == "width" || name == "height" || name == "depth" || name == "dof" || name == "dof_mode";
}

// A JSON value as the table takes it; throws on another JSON type.
SettingValue settingValueFrom(const json& j, const SettingSpec& spec) {
    switch (spec.kind()) {
        case SettingKind::Switch: return j.get<bool>();
        case SettingKind::Choice: return j.get<std::string>();
        case SettingKind::Integer:
            if (!j.is_number_integer()) throw std::invalid_argument(std::string(spec.name) + " must be a whole number");
            return j.get<int64_t>();
        case SettingKind::Number: return j.get<double>();
    }
    throw std::invalid_argument(std::string(spec.name) + " was not understood");
}

json settingJson(const RenderSettings& settings, const SettingSpec& spec) {
    return std::visit([](const auto& value) { return json(value); }, settingValue(settings, spec));
}

const char* dofControl(const RenderSettings& s) {
    if (!s.depthOfField) return "off";
    return s.dofMode == DofMode::Disk ? "disk" : "course";
}

// What the page builds its controls from: every setting of the table it does not lay out
// itself, with its kind, default, range or choices and help.
json settingControlsJson() {
    json controls = json::array();
    for (const SettingSpec& spec : renderSettingsTable()) {
        if (viewerOwnControl(spec.name)) continue;
        static const char* const kKinds[] = {"integer", "number", "switch", "choice"};
        json control{{"name", spec.name}, {"kind", kKinds[int(spec.kind())]}, {"help", spec.help},
                     {"default", settingJson(RenderSettings{}, spec)}};
        if (spec.kind() == SettingKind::Integer || spec.kind() == SettingKind::Number) {
            control["min"] = spec.minimum;
            control["max"] = spec.maximum;
        }
        for (const SettingChoice& choice : spec.choices) control["choices"].push_back(choice.name);
        controls.push_back(control);
    }
    return controls;
}

// A view request from the page: camera and the settings. Throws on anything malformed.
View parseView(const std::string& body, const View& current) {
    json j = json::parse(body);
    if (!j.is_object()) throw std::invalid_argument("not an object");
    View view = current;
    if (j.contains("position")) view.camera.position = vec3From(j["position"]);
    if (j.contains("look")) view.camera.look = vec3From(j["look"]);
    if (j.contains("up")) view.camera.up = vec3From(j["up"]);
    if (length(view.camera.look) < 1e-9 || length(cross(view.camera.look, view.camera.up)) < 1e-12)
        throw std::invalid_argument("look must be non-zero and not along up");
    RenderSettings& s = view.settings;
    s.width = intIn(j, "width", kMinViewSide, kMaxViewSide, s.width);
    s.height = intIn(j, "height", kMinViewSide, kMaxViewSide, s.height);
    s.maxDepth = intIn(j, "depth", 0, kMaxViewDepth, s.maxDepth);
    for (const SettingSpec& spec : renderSettingsTable())
        if (!viewerOwnControl(spec.name) && j.contains(spec.name))
            setSetting(s, spec, settingValueFrom(j[spec.name], spec), spec.name);
    if (j.contains("dof")) {
        std::string dof = j["dof"].get<std::string>();
        if (dof != "off" && dof != "course" && dof != "disk") throw std::invalid_argument("dof must be off, course or disk");
        s.depthOfField = dof != "off";
        if (dof != "off") setSetting(s, *findSetting("dof_mode"), dof, "dof");
    }
    return view;
}

std::string antialiasName(AntialiasMode mode) {
    RenderSettings settings;
    settings.antialias = mode;
    return std::get<std::string>(settingValue(settings, *findSetting("aa")));
}

// What a frame is: the view (request number) and scene (reload number) it shows, and
// whether it is the quick preview of a change or the view at rest, refined.
struct FrameKind {
    uint64_t view = 0, scene = 0;
    AntialiasMode antialias = AntialiasMode::Off;
    bool final = true;  // no refinement follows
};

json frameKindJson(const FrameKind& kind) {
    return {{"view", kind.view}, {"scene", kind.scene}, {"aa", antialiasName(kind.antialias)}, {"final", kind.final}};
}

// Everything the server threads share, under one mutex.
class Session {
public:
    Session(const ViewerOptions& options, std::unique_ptr<FrameSource> source)
        : options_(options), source_(std::move(source)), editor_(options.scene, options.load) {
        scene_ = editor_.scene();
        sceneTime_ = lastWrite();
        view_ = {scene_->camera, options.settings};
    }

    void start() {
        renderThread_ = std::thread([this] { renderLoop(); });
        watchThread_ = std::thread([this] { watchLoop(); });
    }

    json state() {
        std::lock_guard lock(mutex_);
        json state{{"scene", options_.scene.filename().string()}, {"device", source_->deviceName()},
                   {"position", vecJson(view_.camera.position)}, {"look", vecJson(view_.camera.look)},
                   {"up", vecJson(view_.camera.up)}, {"width", view_.settings.width},
                   {"height", view_.settings.height}, {"depth", view_.settings.maxDepth},
                   {"dof", dofControl(view_.settings)}, {"error", sceneError_}, {"view", requested_},
                   {"scene_version", sceneVersion_}};
        state.update(editorStateLocked());
        for (const SettingSpec& spec : renderSettingsTable())
            if (!viewerOwnControl(spec.name)) state[std::string(spec.name)] = settingJson(view_.settings, spec);
        return state;
    }

    // A new view: the frame in flight is cancelled and the latest request alone is rendered.
    void request(const std::string& body) {
        std::lock_guard lock(mutex_);
        view_ = parseView(body, view_);
        newRequest();
    }

    // The editor's part of the state: where "save scene" writes, whether there is something
    // to undo or redo, the lights. Called with mutex_ held.
    json editorStateLocked() const {
        return {{"file", std::filesystem::absolute(editor_.file()).lexically_normal().string()},
                {"modified", editor_.modified()}, {"can_undo", editor_.canUndo()},
                {"can_redo", editor_.canRedo()}, {"lights", editor_.lightsJson()},
                {"editable", !options_.token.empty()}};
    }

    // What pixel (x, y) of the current view shows (SceneEditor::pick).
    json pick(int x, int y) {
        std::lock_guard lock(mutex_);
        return editor_.pick(view_.camera, view_.settings, x, y);
    }

    json object(int id) {
        std::lock_guard lock(mutex_);
        return editor_.objectJson(id);
    }

    // An edit, undo, redo or save from the page; answers the editor's state after it (and
    // the edited object). A change to the scene re-renders the view, preview first.
    json edit(const std::string& action, const std::string& body) {
        std::lock_guard lock(mutex_);
        json request = body.empty() ? json::object() : json::parse(body);
        json out = json::object();
        if (action == "edit") {
            editor_.edit(request);
            if (request.contains("object")) out["object"] = editor_.objectJson(request["object"].get<int>());
        } else if (action == "undo") {
            out["done"] = editor_.undo();
        } else if (action == "redo") {
            out["done"] = editor_.redo();
        } else if (action == "save") {
            std::optional<std::string> as;
            if (request.contains("as")) {
                if (!request["as"].is_string()) throw EditError("save as: the name must be a string");
                as = request["as"].get<std::string>();
            }
            const bool replace = request.contains("replace") && request["replace"].is_boolean() && request["replace"].get<bool>();
            const std::filesystem::path saved = editor_.save(as, replace);
            // Its own save is not a change on disk to reload (which would clear the history).
            sceneTime_ = lastWrite();
            log("saved " + quotedForMessage(saved.string()));
            out["saved"] = saved.string();
        }
        if (editor_.scene() != scene_) {
            scene_ = editor_.scene();
            ++sceneVersion_;
            newRequest();
        }
        out.update(editorStateLocked());
        out["scene_version"] = sceneVersion_;
        return out;
    }

    // The explanation names the view and scene it was made for, so that the page can tell
    // when a later frame has made it stale.
    json explain(int x, int y) {
        std::shared_ptr<const Scene> scene;
        View view;
        uint64_t viewId = 0, sceneVersion = 0;
        {
            std::lock_guard lock(mutex_);
            scene = scene_;
            view = view_;
            viewId = requested_;
            sceneVersion = sceneVersion_;
        }
        if (x < 0 || y < 0 || x >= view.settings.width || y >= view.settings.height)
            throw std::invalid_argument("pixel outside the image");
        Scene viewed = *scene;
        viewed.camera = view.camera;
        json tree = explanationJson(explainPixel(viewed, view.settings, x, y), viewed);
        tree["view"] = viewId;
        tree["scene_version"] = sceneVersion;
        return tree;
    }

    // What one /events client has been sent so far.
    struct Cursor {
        uint64_t id = 0;  // the order the stream was opened in
        uint64_t frame = 0;
        size_t sent = 0;
        bool doneSent = false;
        std::string error;
        uint64_t sceneVersion = 0;
    };

    // Writes, as server-sent events, what happened since `cursor`; waits up to a second.
    bool stream(httplib::DataSink& sink, Cursor& cursor) {
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
                out += "event: scene\ndata: " + json{{"error", error}, {"version", sceneVersion}}.dump() + "\n\n";
            }
            if (frame != frame_) {
                frame = frame_;
                sent = 0;
                doneSent = false;
                json event{{"frame", frame_}, {"width", frameWidth_}, {"height", frameHeight_}};
                event.update(frameKindJson(frameKind_));
                out += "event: frame\ndata: " + event.dump() + "\n\n";
            }
            for (; sent < tiles_.size(); ++sent) {
                const FrameTile& t = tiles_[sent];
                out += "event: tile\ndata: " +
                       json{{"frame", frame_}, {"x", t.x}, {"y", t.y}, {"w", t.width}, {"h", t.height},
                            {"rgb", base64(t.rgb)}}.dump() + "\n\n";
            }
            if (frameDone_ && sent == tiles_.size() && !doneSent) {
                doneSent = true;
                out += "event: done\ndata: " + doneJson_.dump() + "\n\n";
            }
        }
        if (out.empty()) out = ": keep-alive\n\n";  // notices a client that has gone
        return sink.write(out.data(), out.size());
    }

    uint64_t openStream() {
        std::lock_guard lock(mutex_);
        return ++streamsOpened_;
    }

    void stop() {
        {
            std::lock_guard lock(mutex_);
            stop_ = true;
            cancel_ = true;
            changed_.notify_all();
        }
        renderThread_.join();
        watchThread_.join();
    }

private:
    std::filesystem::file_time_type lastWrite() const {
        std::error_code ec;
        return std::filesystem::last_write_time(options_.scene, ec);
    }

    // A new view or scene: the frame in flight is cancelled, the next one is its preview.
    // Called with mutex_ held.
    void newRequest() {
        ++requested_;
        lastRequestAt_ = Clock::now();
        cancel_ = true;
        changed_.notify_all();
    }

    // What to render next, waiting for it: the preview of the latest request, or its
    // refinement once the view has rested for kRestDelay. False when stopping.
    bool nextFrame(std::unique_lock<std::mutex>& lock, uint64_t& rendered, bool& refined, FrameKind& kind) {
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

    void renderLoop() {
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
                // The viewer stays up: the page and the terminal say why, the next change
                // tries again.
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
            doneJson_ = {{"frame", frame_}, {"seconds", seconds}, {"rays", rays},
                         {"mrays", seconds > 0 ? double(rays) / seconds / 1e6 : 0.0},
                         {"device", source_->deviceName()}};
            doneJson_.update(frameKindJson(kind));
            changed_.notify_all();
        }
    }

    void log(const std::string& message) const {
        if (options_.log) options_.log(message);
    }

    // Saving the scene reloads it; a broken save keeps the last good scene and shows why.
    void watchLoop() {
        for (;;) {
            {
                std::unique_lock lock(mutex_);
                if (changed_.wait_for(lock, kWatchInterval, [&] { return stop_; })) return;
            }
            auto time = lastWrite();
            if (time == sceneTime_) continue;
            sceneTime_ = time;
            const std::string name = options_.scene.filename().string();
            try {
                std::lock_guard lock(mutex_);
                editor_.reload();
                log("reloaded " + name + (editor_.canUndo() ? "" : " (the edits' history starts again)"));
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

    const ViewerOptions& options_;
    std::unique_ptr<FrameSource> source_;
    SceneEditor editor_;  // the document, its edits and history, under mutex_
    std::mutex mutex_;
    std::condition_variable changed_;
    std::shared_ptr<const Scene> scene_;
    std::filesystem::file_time_type sceneTime_;
    std::string sceneError_;     // shown in the page: a broken save, or a failed frame
    bool errorIsFrames_ = false;  // sceneError_ is a failed frame's
    View view_;
    uint64_t requested_ = 0;     // view requests so far: the id of the latest view
    uint64_t sceneVersion_ = 0;  // successful reloads so far
    Clock::time_point lastRequestAt_ = Clock::now();
    FrameKind frameKind_;        // what the frame frame_ shows
    std::atomic<bool> cancel_{false};
    bool stop_ = false;
    uint64_t frame_ = 0;
    int frameWidth_ = 0, frameHeight_ = 0;
    uint64_t streamsOpened_ = 0;
    std::vector<FrameTile> tiles_;  // the current frame's only: memory stays one frame
    bool frameDone_ = false;
    json doneJson_;
    std::thread renderThread_, watchThread_;
};

void badRequest(httplib::Response& response, const std::string& why) {
    response.status = 400;
    response.set_content(json{{"error", why}}.dump(), "application/json");
}

// A whole number from the query: "x must be a whole number" rather than std::stoi's "stoi".
int intParameter(const httplib::Request& request, const char* name) {
    const std::string text = request.get_param_value(name);
    int value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc() || end != text.data() + text.size())
        throw std::invalid_argument(std::string(name) + " must be a whole number" +
                                    (error == std::errc::result_out_of_range ? " in range" : "") + ", not '" +
                                    quotedForMessage(text, 40) + "'");
    return value;
}

// Whether a request comes with a body: the guard runs before cpp-httplib reads it, so its
// headers tell.
bool carriesBody(const httplib::Request& request) {
    const std::string length = request.get_header_value("Content-Length");
    return (!length.empty() && length != "0") || request.has_header("Transfer-Encoding");
}

// Headers every answer carries: it is never framed, read by another origin or sniffed.
void setProtectiveHeaders(httplib::Response& response) {
    response.set_header("X-Content-Type-Options", "nosniff");
    response.set_header("X-Frame-Options", "DENY");
    response.set_header("Cross-Origin-Resource-Policy", "same-origin");
    response.set_header("Referrer-Policy", "no-referrer");
}

// The check every request passes first (viewer/request_guard.h). A first visit to the page
// with the token in its query gets the cookie and is sent on to the bare URL.
httplib::Server::HandlerResponse guardRequest(const httplib::Request& request, httplib::Response& response,
                                              const GuardPolicy& policy) {
    using Result = httplib::Server::HandlerResponse;
    setProtectiveHeaders(response);
    const RequestFacts facts{request.method,
                             request.path,
                             request.get_header_value("Host"),
                             request.get_header_value("Origin"),
                             request.get_header_value("Sec-Fetch-Site"),
                             request.get_header_value("Sec-Fetch-Mode"),
                             request.get_header_value("Sec-Fetch-Dest"),
                             request.get_header_value("Content-Type"),
                             request.get_param_value("token"),
                             request.get_header_value("Authorization"),
                             request.get_header_value("Cookie"),
                             carriesBody(request)};
    const GuardVerdict verdict = checkRequest(facts, policy);
    if (verdict.status != 0) {
        response.status = verdict.status;
        response.set_content(json{{"error", verdict.message}}.dump(), "application/json");
        return Result::Handled;
    }
    if (!verdict.setCookie.empty()) {
        response.set_header("Set-Cookie", verdict.setCookie);
        response.set_redirect("/", 303);
        return Result::Handled;
    }
    return Result::Unhandled;
}

// An error answer that cpp-httplib made itself (a body over the limit, a request it could
// not read) says what went wrong, as every other answer does.
httplib::Server::HandlerResponse explainError(const httplib::Request&, httplib::Response& response) {
    if (!response.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
    std::string why = "the request was not understood (an HTTP request with a JSON body, and a Content-Length "
                      "for a POST)";
    if (response.status == 413)
        why = "the request's body is over the " + std::to_string(kMaxRequestBody / 1024) + " KiB limit";
    else if (response.status == 404)
        why = "there is no such route (the viewer serves /, /state, /settings, /events, /view, /pick, /object, "
              "/explain, /edit, /undo, /redo and /save)";
    response.set_content(json{{"error", why}}.dump(), "application/json");
    return httplib::Server::HandlerResponse::Handled;
}

// The page, with its token written in (request_guard.h says why the page holds it).
std::string pageWithToken(const std::string& token) {
    std::string page = kViewerPage;
    const std::string placeholder = R"(<meta name="ray-token" content="">)";
    const size_t at = page.find(placeholder);
    if (at != std::string::npos) page.replace(at, placeholder.size(), R"(<meta name="ray-token" content=")" + token + "\">");
    return page;
}

void defineRoutes(httplib::Server& server, Session& session, const std::string& token) {
    const bool editable = !token.empty();
    server.Get(kPagePath, [page = pageWithToken(token)](const httplib::Request&, httplib::Response& response) {
        response.set_header("Cache-Control", "no-store");
        response.set_header("Content-Security-Policy", "frame-ancestors 'none'");
        response.set_content(page, "text/html; charset=utf-8");
    });
    server.Get("/settings", [](const httplib::Request&, httplib::Response& response) {
        response.set_content(settingControlsJson().dump(), "application/json");
    });
    server.Get("/state", [&](const httplib::Request&, httplib::Response& response) {
        response.set_content(session.state().dump(), "application/json");
    });
    server.Post("/view", [&](const httplib::Request& request, httplib::Response& response) {
        try {
            session.request(request.body);
            response.set_content("{}", "application/json");
        } catch (const std::exception& e) {
            badRequest(response, e.what());
        }
    });
    server.Get("/explain", [&](const httplib::Request& request, httplib::Response& response) {
        try {
            response.set_content(session.explain(intParameter(request, "x"), intParameter(request, "y")).dump(),
                                 "application/json");
        } catch (const std::exception& e) {
            badRequest(response, e.what());
        }
    });
    server.Get("/pick", [&](const httplib::Request& request, httplib::Response& response) {
        try {
            response.set_content(session.pick(intParameter(request, "x"), intParameter(request, "y")).dump(),
                                 "application/json");
        } catch (const std::exception& e) {
            badRequest(response, e.what());
        }
    });
    server.Get("/object", [&](const httplib::Request& request, httplib::Response& response) {
        try {
            response.set_content(session.object(intParameter(request, "id")).dump(), "application/json");
        } catch (const std::exception& e) {
            badRequest(response, e.what());
        }
    });
    // Editing: only with the access token (a viewer started with --no-token shows the scene
    // and does not change it or its file).
    for (const char* action : {"edit", "undo", "redo", "save"}) {
        server.Post(std::string("/") + action, [&session, action, editable = editable](const httplib::Request& request,
                                                                                     httplib::Response& response) {
            if (!editable) {
                response.status = 403;
                response.set_content(json{{"error", "this viewer was started with --no-token: editing the scene "
                                                    "needs the access token; start ray view without --no-token"}}
                                         .dump(),
                                     "application/json");
                return;
            }
            try {
                response.set_content(session.edit(action, request.body).dump(), "application/json");
            } catch (const FileExists& e) {
                response.status = 409;
                response.set_content(json{{"error", e.what()}, {"exists", true}}.dump(), "application/json");
            } catch (const json::exception& e) {
                badRequest(response, std::string("the edit is not JSON as expected: ") + e.what());
            } catch (const std::exception& e) {
                badRequest(response, e.what());
            }
        });
    }
    server.Get("/events", [&](const httplib::Request&, httplib::Response& response) {
        response.set_header("Cache-Control", "no-cache");
        auto cursor = std::make_shared<Session::Cursor>();
        cursor->id = session.openStream();
        response.set_chunked_content_provider("text/event-stream", [&session, cursor](size_t, httplib::DataSink& sink) {
            return session.stream(sink, *cursor);
        });
    });
}

// SO_REUSEADDR alone: a restarted viewer may take its port back from connections in
// TIME_WAIT, but a port another server listens on stays refused. (cpp-httplib's default
// also sets SO_REUSEPORT, under which two viewers both listened and shared the requests.)
void exclusivePortOptions(socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
}

// Why binding failed, asked again of the system: cpp-httplib only says that it did.
int bindFailure(const std::string& address, int port) {
    addrinfo hints{}, *found = nullptr;
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_PASSIVE;
    if (getaddrinfo(address.c_str(), std::to_string(port).c_str(), &hints, &found) != 0 || !found) return EADDRNOTAVAIL;
    int error = 0;
    int sock = socket(found->ai_family, found->ai_socktype, found->ai_protocol);
    if (sock < 0) error = errno;
    else {
        exclusivePortOptions(sock);
        if (bind(sock, found->ai_addr, found->ai_addrlen) != 0) error = errno;
        close(sock);
    }
    freeaddrinfo(found);
    return error;
}

[[noreturn]] void throwCannotListen(const std::string& address, int port) {
    const int error = bindFailure(address, port);
    const std::string where = address + ":" + std::to_string(port);
    if (error == EADDRINUSE)
        throw AddressInUse("port " + std::to_string(port) + " on " + address +
                           " is already in use (another ray view, or another server); stop it, or choose another "
                           "port: --port N, or --port 0 for any free one");
    throw std::runtime_error("cannot listen on " + where + (error ? std::string(": ") + std::strerror(error) : "") +
                             "; try another --port or --bind");
}

}  // namespace

void runViewer(const ViewerOptions& options, std::unique_ptr<FrameSource> source) {
    Session session(options, std::move(source));
    httplib::Server server;
    server.set_socket_options(exclusivePortOptions);
    server.set_payload_max_length(kMaxRequestBody);
    server.set_error_handler(httplib::Server::HandlerWithResponse(explainError));
    // A client that stops reading is dropped after this long instead of holding a thread.
    server.set_write_timeout(5, 0);
    server.set_read_timeout(5, 0);
    server.set_keep_alive_max_count(100);
    server.new_task_queue = [] { return new httplib::ThreadPool(kServerThreads); };
    defineRoutes(server, session, options.token);
    int port = options.port;
    if (port == 0) port = server.bind_to_any_port(options.address);
    else if (!server.bind_to_port(options.address, port)) port = -1;
    if (port < 0) throwCannotListen(options.address, options.port);
    // The cookie's name and the Host check hold the port, known only now (--port 0).
    const GuardPolicy policy{options.token, port, isLoopbackAddress(options.address)};
    server.set_pre_routing_handler([policy](const httplib::Request& request, httplib::Response& response) {
        return guardRequest(request, response, policy);
    });
    session.start();
    if (options.onListening) options.onListening(port);
    server.listen_after_bind();
    session.stop();
}

}  // namespace ray
