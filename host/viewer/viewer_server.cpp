#include "viewer/viewer_server.h"

#include <httplib.h>

#include <chrono>
#include <condition_variable>
#include <cmath>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>

#include "explain/explanation_report.h"
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

// A view request from the page: camera and the switches. Throws on anything malformed.
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
    for (auto [key, flag] : {std::pair{"shadows", &s.shadows}, std::pair{"reflections", &s.reflections},
                             std::pair{"refraction", &s.refraction}, std::pair{"textures", &s.textures},
                             std::pair{"fresnel", &s.fresnel}, std::pair{"course_meshes", &s.courseMeshes}})
        if (j.contains(key)) *flag = j[key].get<bool>();
    if (j.contains("aa")) {
        std::string aa = j["aa"].get<std::string>();
        if (aa == "off") s.antialias = AntialiasMode::Off;
        else if (aa == "course") s.antialias = AntialiasMode::Course;
        else throw std::invalid_argument("aa must be off or course");
    }
    if (j.contains("dof")) {  // depth of field: off, or --dof's course | disk
        std::string dof = j["dof"].get<std::string>();
        if (dof != "off" && dof != "course" && dof != "disk") throw std::invalid_argument("dof must be off, course or disk");
        s.depthOfField = dof != "off";
        if (dof != "off") s.dofMode = dof == "disk" ? DofMode::Disk : DofMode::Course;
    }
    return view;
}

// Everything the server threads share, under one mutex.
class Session {
public:
    Session(const ViewerOptions& options, std::unique_ptr<FrameSource> source)
        : options_(options), source_(std::move(source)) {
        scene_ = std::make_shared<Scene>(loadScene(options.scene, options.load));
        sceneTime_ = lastWrite();
        view_ = {scene_->camera, options.settings};
    }

    void start() {
        renderThread_ = std::thread([this] { renderLoop(); });
        watchThread_ = std::thread([this] { watchLoop(); });
    }

    json state() {
        std::lock_guard lock(mutex_);
        return {{"scene", options_.scene.filename().string()}, {"device", source_->deviceName()},
                {"position", vecJson(view_.camera.position)}, {"look", vecJson(view_.camera.look)},
                {"up", vecJson(view_.camera.up)}, {"width", view_.settings.width},
                {"height", view_.settings.height}, {"depth", view_.settings.maxDepth},
                {"shadows", view_.settings.shadows}, {"reflections", view_.settings.reflections},
                {"refraction", view_.settings.refraction}, {"textures", view_.settings.textures},
                {"fresnel", view_.settings.fresnel}, {"course_meshes", view_.settings.courseMeshes},
                {"aa", view_.settings.antialias == AntialiasMode::Off ? "off" : "course"},
                {"dof", !view_.settings.depthOfField                  ? "off"
                        : view_.settings.dofMode == DofMode::Disk ? "disk"
                                                                  : "course"},
                {"error", sceneError_}};
    }

    // A new view: the frame in flight is cancelled and the latest request alone is rendered.
    void request(const std::string& body) {
        std::lock_guard lock(mutex_);
        view_ = parseView(body, view_);
        ++requested_;
        cancel_ = true;
        changed_.notify_all();
    }

    json explain(int x, int y) {
        std::shared_ptr<const Scene> scene;
        View view;
        {
            std::lock_guard lock(mutex_);
            scene = scene_;
            view = view_;
        }
        if (x < 0 || y < 0 || x >= view.settings.width || y >= view.settings.height)
            throw std::invalid_argument("pixel outside the image");
        Scene viewed = *scene;
        viewed.camera = view.camera;
        return explanationJson(explainPixel(viewed, view.settings, x, y), viewed);
    }

    // What one /events client has been sent so far.
    struct Cursor {
        uint64_t id = 0;  // the order the stream was opened in
        uint64_t frame = 0;
        size_t sent = 0;
        bool doneSent = false;
        std::string error;
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
        std::string out;
        {
            std::unique_lock lock(mutex_);
            changed_.wait_for(lock, std::chrono::seconds(1), [&] {
                return frame != frame_ || sent < tiles_.size() || error != sceneError_ || stop_ ||
                       (frameDone_ && !doneSent);
            });
            if (stop_ || id + kMaxStreams < streamsOpened_) return false;
            if (error != sceneError_) {
                error = sceneError_;
                out += "event: scene\ndata: " + json{{"error", error}}.dump() + "\n\n";
            }
            if (frame != frame_) {
                frame = frame_;
                sent = 0;
                doneSent = false;
                out += "event: frame\ndata: " +
                       json{{"frame", frame_}, {"width", frameWidth_}, {"height", frameHeight_}}.dump() + "\n\n";
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

    void renderLoop() {
        uint64_t rendered = ~uint64_t(0);
        for (;;) {
            std::shared_ptr<const Scene> scene;
            View view;
            {
                std::unique_lock lock(mutex_);
                changed_.wait(lock, [&] { return stop_ || requested_ != rendered; });
                if (stop_) return;
                rendered = requested_;
                scene = scene_;
                view = view_;
                cancel_ = false;
                ++frame_;
                tiles_.clear();
                frameDone_ = false;
                frameWidth_ = view.settings.width;
                frameHeight_ = view.settings.height;
                changed_.notify_all();
            }
            auto start = Clock::now();
            uint64_t rays = source_->renderFrame(scene, view.camera, view.settings,
                                                 [&](const FrameTile& tile) {
                                                     std::lock_guard lock(mutex_);
                                                     tiles_.push_back(tile);
                                                     changed_.notify_all();
                                                 },
                                                 cancel_);
            double seconds = std::chrono::duration<double>(Clock::now() - start).count();
            std::lock_guard lock(mutex_);
            if (cancel_) continue;
            frameDone_ = true;
            doneJson_ = {{"frame", frame_}, {"seconds", seconds}, {"rays", rays},
                         {"mrays", seconds > 0 ? double(rays) / seconds / 1e6 : 0.0},
                         {"device", source_->deviceName()}};
            changed_.notify_all();
        }
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
            try {
                auto scene = std::make_shared<Scene>(loadScene(options_.scene, options_.load));
                std::lock_guard lock(mutex_);
                scene_ = scene;
                sceneError_.clear();
                ++requested_;
                cancel_ = true;
                changed_.notify_all();
            } catch (const std::exception& e) {
                std::lock_guard lock(mutex_);
                sceneError_ = e.what();
                changed_.notify_all();
            }
        }
    }

    const ViewerOptions& options_;
    std::unique_ptr<FrameSource> source_;
    std::mutex mutex_;
    std::condition_variable changed_;
    std::shared_ptr<const Scene> scene_;
    std::filesystem::file_time_type sceneTime_;
    std::string sceneError_;
    View view_;
    uint64_t requested_ = 0;
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

void defineRoutes(httplib::Server& server, Session& session) {
    server.Get("/", [](const httplib::Request&, httplib::Response& response) {
        response.set_content(kViewerPage, "text/html; charset=utf-8");
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
            int x = std::stoi(request.get_param_value("x")), y = std::stoi(request.get_param_value("y"));
            response.set_content(session.explain(x, y).dump(), "application/json");
        } catch (const std::exception& e) {
            badRequest(response, e.what());
        }
    });
    server.Get("/events", [&](const httplib::Request&, httplib::Response& response) {
        response.set_header("Cache-Control", "no-cache");
        auto cursor = std::make_shared<Session::Cursor>();
        cursor->id = session.openStream();
        response.set_chunked_content_provider("text/event-stream", [&session, cursor](size_t, httplib::DataSink& sink) {
            return session.stream(sink, *cursor);
        });
    });
}

}  // namespace

void runViewer(const ViewerOptions& options, std::unique_ptr<FrameSource> source) {
    Session session(options, std::move(source));
    httplib::Server server;
    server.set_payload_max_length(kMaxRequestBody);
    // A client that stops reading is dropped after this long instead of holding a thread.
    server.set_write_timeout(5, 0);
    server.set_read_timeout(5, 0);
    server.set_keep_alive_max_count(100);
    server.new_task_queue = [] { return new httplib::ThreadPool(kServerThreads); };
    defineRoutes(server, session);
    int port = options.port;
    if (port == 0) port = server.bind_to_any_port(options.address);
    else if (!server.bind_to_port(options.address, port)) port = -1;
    if (port < 0)
        throw std::runtime_error("cannot listen on " + options.address + ":" + std::to_string(options.port) +
                                 "; try another --port");
    session.start();
    if (options.onListening) options.onListening(port);
    server.listen_after_bind();
    session.stop();
}

}  // namespace ray
