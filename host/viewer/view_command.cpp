#include "viewer/view_command.h"

#include <CLI/CLI.hpp>
#include <ctime>
#include <iostream>

#include "app/cli.h"
#include "app/command_module_abi.h"
#include "app/render_command.h"
#include "core/message_text.h"
#include "devices/renderer.h"
#include "opencl/opencl_device.h"
#include "scene/file_search.h"
#include "viewer/access_token.h"
#include "viewer/new_scene.h"
#include "viewer/request_guard.h"
#include "viewer/viewer_server.h"

namespace ray {

namespace {

const char* const kViewIntro = R"(usage: ray view <scene.xml> [options]

A live viewer and modeler in the browser: drag to orbit, shift-drag to pan, wheel to zoom,
click to select and explain a pixel. A scene file that does not exist opens as a new scene
(a camera and a light), written there when saved. Saving the scene reloads it. Each change is drawn at once with one sample a
pixel, then, once the view rests, with the antialiasing of --aa (by default the course's, as
`ray`), the image `ray <scene.xml> <width> <height>` makes of that view. The render
settings below set the view's first state; the page changes them.

options:
  --port N                 TCP port (0: any free one; default 8123). A port in use is
                           refused
  --bind ADDRESS           address to listen on (default 127.0.0.1; anything else exposes
                           the viewer to the network)
  --no-token               open to anyone who can reach the port. By default the printed
                           URL holds a random access token (kept in a cookie after the
                           first visit) and every request without it gets 403, so that
                           other users of the machine cannot use the viewer
  --width N, --height N    image size (8..2048); by default the view fills the page's
                           window and follows its size
  --depth N                recursion depth (0..16; default 4)
  --device D               auto|cpu|gpu|all|<index>|<list>: OpenCL devices, the scene
                           packed once; ref: the reference renderer
  --undo-memory MIB        the most memory the undo history holds (1..65536; default 64);
                           past it the oldest steps are dropped
  -h, --help               this text
)";

std::string viewUsage() {
    return kViewIntro + renderSettingsHelp() +
           "\nexit status: 0 stopped, 2 bad input or arguments, 3 the port is in use or the server or\n"
           "             device cannot start\n";
}

struct ViewCommand {
    ViewerOptions options;
    std::vector<std::string> positionals;
    std::vector<std::filesystem::path> searchPaths;
    std::string device = "auto";
    bool noToken = false;
    bool help = false;
};

void defineOptions(CLI::App& app, ViewCommand& c) {
    RenderSettings& s = c.options.settings;
    app.set_help_flag();  // viewUsage() instead of CLI11's
    addSwitch(app, "-h,--help", [&] { c.help = true; });
    addValueOption(app, "--port", [&](const std::string& v) { c.options.port = parseInt(v, "--port", 0, 65535); });
    addValueOption(app, "--bind", [&](const std::string& v) {
        if (v.empty()) throw UsageError("--bind needs an address, such as 127.0.0.1");
        c.options.address = v;
    });
    addSwitch(app, "--no-token", [&] { c.noToken = true; });
    addValueOption(app, "--undo-memory", [&](const std::string& v) {
        c.options.historyLimit = size_t(parseInt(v, "--undo-memory", 1, 65536)) << 20;
    });
    addValueOption(app, "--width", [&](const std::string& v) {
        s.width = parseInt(v, "--width", kMinViewSide, kMaxViewSide);
        c.options.fitWindow = false;
    });
    addValueOption(app, "--height", [&](const std::string& v) {
        s.height = parseInt(v, "--height", kMinViewSide, kMaxViewSide);
        c.options.fitWindow = false;
    });
    addValueOption(app, "--depth", [&](const std::string& v) { s.maxDepth = parseInt(v, "--depth", 0, kMaxViewDepth); });
    addValueOption(app, "--device", [&](const std::string& v) {
        if (!isDeviceSelection(v))
            throw UsageError("--device must be auto, cpu, gpu, all, ref, a device index or a list such as 0,2, not '" +
                             v + "'");
        c.device = v;
    });
    addRenderSettingOptions(app, s, c.searchPaths);
    app.add_option("scene", c.positionals);
}

std::string timeOfDay() {
    std::time_t now = std::time(nullptr);
    char text[16];
    std::strftime(text, sizeof text, "%H:%M:%S", std::localtime(&now));
    return text;
}

void finishOptions(ViewCommand& c) {
    if (c.positionals.empty()) throw UsageError("no scene file given");
    if (c.positionals.size() > 1) throw UsageError("too many arguments: '" + c.positionals[1] + "'");
    ViewerOptions& options = c.options;
    options.scene = c.positionals[0];
    options.newScene = opensAsNewScene(options.scene);
    options.load.searchPaths = c.searchPaths;
    for (auto& p : searchPathsFromEnvironment()) options.load.searchPaths.push_back(p);
    options.load.warn = [](const std::string& message) { std::cerr << message << "\n"; };
    if (!c.noToken) options.token = newAccessToken();
    // The URL is the only place the token is ever printed.
    options.onListening = [&options](int port) {
        std::cout << "ray view: http://" << options.address << ":" << port << "/"
                  << (options.token.empty() ? "" : "?token=" + options.token) << std::endl;
        if (options.newScene)
            std::cout << "ray view: " << quotedForMessage(options.scene.string())
                      << " does not exist: a new scene (a camera and a light), written there when saved" << std::endl;
    };
    options.log = [](const std::string& message) { std::cerr << "ray view " << timeOfDay() << ": " << message << std::endl; };
}

}  // namespace

int runViewCommand(const std::vector<std::string>& args) {
    CLI::App app{"ray view", "ray view"};
    ViewCommand command;
    command.options.settings.width = 640;
    command.options.settings.height = 480;
    // The view at rest is refined to --aa (the CLI's default unless given); while the
    // camera moves, frames take one sample a pixel (viewer_server.h).
    defineOptions(app, command);
    try {
        parseArguments(app, args);
        if (command.help) {
            std::cout << viewUsage();
            return 0;
        }
        finishOptions(command);
    } catch (const UsageError& e) {
        std::cerr << "ray view: " << e.what() << "\n(see ray view --help)\n";
        return 2;
    }
    const ViewerOptions& options = command.options;
    if (!isLoopbackAddress(options.address))
        std::cerr << "ray view: warning: listening on " << options.address
                  << ", not only this machine: anyone who can reach it can use the viewer"
                  << (options.token.empty() ? "" : " if they learn its URL") << "\n";
    try {
        runViewer(options, makeFrameSource(command.device));
        return 0;
    } catch (const InputError& e) {
        std::cerr << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "ray view: " << e.what() << "\n";
        return kExitRuntime;
    }
}

}  // namespace ray

// The module's entry point (app/command_module_abi.h).
extern "C" int ray_view_main(int argc, const char* const* argv) {
    try {
        return ray::runViewCommand(std::vector<std::string>(argv, argv + argc));
    } catch (...) {  // none crosses the C interface
        return ray::reportFailure(std::current_exception());
    }
}
