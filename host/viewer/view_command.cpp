#include "viewer/view_command.h"

#include <CLI/CLI.hpp>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <ctime>
#include <iostream>
#include <sstream>

#include "app/cli.h"
#include "app/command_module_abi.h"
#include "app/render_command.h"
#include "core/message_text.h"
#include "devices/renderer.h"
#include "opencl/opencl_device.h"
#include "scene/file_search.h"
#include "viewer/access_token.h"
#include "viewer/new_scene.h"
#include "viewer/recovery.h"
#include "viewer/request_guard.h"
#include "viewer/stop_signals.h"
#include "viewer/viewer_server.h"

namespace ray {

namespace {

const char* const kViewIntro = R"(usage: ray view <scene.xml> [options]

A live viewer and modeler in the browser: drag to orbit, shift-drag to pan, wheel to zoom,
click to select and explain a pixel. A scene file that does not exist opens as a new scene
(a camera and a light), written there when saved (new.json: as the course's JSON). Saving the scene reloads it. Each change is drawn at once with one sample a
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
  --recover                open the scene with the unsaved edits a viewer of it left when it
                           was stopped (they are kept in ~/.local/state/ray/recovery/, or
                           $XDG_STATE_HOME/ray/recovery/): unsaved until saved
  --frame-ancestors SOURCES
                           the pages that may show the viewer inside a frame: a
                           Content-Security-Policy source list such as http://localhost:*
                           (cs123ray.view gives a notebook's); the frame opens the URL with
                           its token. By default the page is never framed
  -h, --help               this text
)";

std::string viewUsage() {
    return kViewIntro + renderSettingsHelp() +
           "\nexit status: 2 bad input or arguments, 3 the port is in use or the server or device\n"
           "             cannot start; stopped: 130 (Ctrl-C), 143 (SIGTERM), 129 (the terminal closed),\n"
           "             the unsaved edits kept first\n";
}

struct ViewCommand {
    ViewerOptions options;
    std::vector<std::string> positionals;
    std::vector<std::filesystem::path> searchPaths;
    std::string device = "auto";
    bool noToken = false;
    bool recover = false;
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
    addSwitch(app, "--recover", [&] { c.recover = true; });
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
    addValueOption(app, "--frame-ancestors", [&](const std::string& v) {
        if (v.empty() || v.find_first_of(";,\r\n'\"") != std::string::npos)
            throw UsageError("--frame-ancestors takes sources such as http://localhost:* (separated by spaces; no "
                             "quotes, commas or semicolons), not '" + v + "'");
        c.options.frameAncestors = v;
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

const char* signalName(int signal) {
    switch (signal) {
        case SIGINT: return "Ctrl-C";
        case SIGTERM: return "SIGTERM";
        case SIGHUP: return "SIGHUP, the terminal closed";
        default: return "a signal";
    }
}

// A path as a shell reads it back: as it is when it holds no character a shell treats
// specially, else in single quotes.
std::string shellQuoted(const std::string& text) {
    const bool plain = !text.empty() && text.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                                               "0123456789_./-+,:@%") == std::string::npos;
    if (plain) return text;
    std::string quoted = "'";
    for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

// How to open a recovery: the command as the user would type it.
std::string recoverCommand(const std::filesystem::path& scene) {
    return "ray view " + shellQuoted(quotedForMessage(scene.string(), 4096)) + " --recover";
}

// Whether the viewer that wrote a recovery may still be running (another ray view of the
// scene with edits of its own): its process id is in use ("may": ids are reused).
bool writerMayRun(const Recovery& recovery) {
    return recovery.pid > 0 && recovery.pid != getpid() && (::kill(recovery.pid, 0) == 0 || errno == EPERM);
}

// The terminal's line about the newest recovery of the scene, when the viewer did not open it.
std::string offerLine(const Recovery& offer, const std::filesystem::path& scene) {
    std::string notes;
    if (sceneChangedSince(offer, scene)) notes += " (the scene file has changed since)";
    if (writerMayRun(offer))
        notes += " (written by process " + std::to_string(offer.pid) + ", which may be a ray view still running)";
    return "ray view: unsaved edits of " + quotedForMessage(scene.filename().string()) + " from " + offer.writtenText +
           " are kept in " + quotedForMessage(offer.file.string()) + notes + ": open them with `" + recoverCommand(scene) +
           "`, or Restore in the page";
}

// What a stop by a signal says: where the unsaved edits are, or why they could not be kept.
void reportStop(int signal, const RecoveryKeeper::Kept& kept, const std::filesystem::path& scene) {
    std::ostringstream line;
    line << "ray view: stopped (" << signalName(signal) << ")";
    if (!kept.file.empty())
        line << "; the unsaved edits of " << quotedForMessage(scene.filename().string()) << " are kept in "
             << quotedForMessage(kept.file.string()) << ": open them again with `" << recoverCommand(scene) << "`";
    else if (kept.unsaved || !kept.error.empty())
        line << "; the unsaved edits could not be kept: " << kept.error;
    std::cout << line.str() << std::endl;
}

// The recoveries of the scene: --recover opens the newest (none: bad input), the next is
// offered; without it the newest is offered, on the terminal and in the page.
void findRecoveriesOf(ViewCommand& c) {
    ViewerOptions& options = c.options;
    const std::optional<std::filesystem::path> folder = recoveryFolder();
    if (!folder) {
        std::cerr << "ray view: warning: no home folder (HOME is not set): unsaved edits cannot be kept\n";
        if (c.recover) throw UsageError("--recover: no home folder (HOME), so no unsaved edits are kept");
        return;
    }
    options.recoveryFolder = *folder;
    std::vector<Recovery> found =
        findRecoveries(*folder, options.scene, [](const std::string& why) { std::cerr << "ray view: " << why << "\n"; });
    if (c.recover) {
        if (found.empty())
            throw UsageError("--recover: no unsaved edits of " + quotedForMessage(options.scene.string()) +
                             " are kept (in " + quotedForMessage(folder->string()) + ")");
        options.recovered = std::move(found.front());
        found.erase(found.begin());
    }
    if (!found.empty()) options.offer = std::move(found.front());
}

void finishOptions(ViewCommand& c) {
    if (c.positionals.empty()) throw UsageError("no scene file given");
    if (c.positionals.size() > 1) throw UsageError("too many arguments: '" + c.positionals[1] + "'");
    ViewerOptions& options = c.options;
    options.scene = c.positionals[0];
    options.newScene = opensAsNewScene(options.scene);
    findRecoveriesOf(c);
    options.load.searchPaths = c.searchPaths;
    for (auto& p : searchPathsFromEnvironment()) options.load.searchPaths.push_back(p);
    options.load.warn = [](const std::string& message) { std::cerr << message << "\n"; };
    if (!c.noToken) options.token = newAccessToken();
    // The URL is the only place the token is ever printed.
    options.onListening = [&options](int port) {
        std::cout << "ray view: http://" << options.address << ":" << port << "/"
                  << (options.token.empty() ? "" : "?token=" + options.token) << std::endl;
        if (options.newScene && !options.recovered)
            std::cout << "ray view: " << quotedForMessage(options.scene.string())
                      << " does not exist: a new scene (a camera and a light), written there when saved" << std::endl;
        if (options.recovered)
            std::cout << "ray view: opened with the unsaved edits kept in "
                      << quotedForMessage(options.recovered->file.string()) << " from " << options.recovered->writtenText
                      << " (" << quotedForMessage(options.scene.filename().string())
                      << (options.newScene ? " is written when you save)" : " is unchanged until you save)") << std::endl;
        if (options.offer) std::cout << offerLine(*options.offer, options.scene) << std::endl;
    };
    options.onStopSignal = [&options](int signal, const RecoveryKeeper::Kept& kept) {
        reportStop(signal, kept, options.scene);
    };
    options.log = [](const std::string& message) { std::cerr << "ray view " << timeOfDay() << ": " << message << std::endl; };
}

}  // namespace

CommandReference viewCommandReference() {
    CLI::App app{"ray view", "ray view"};
    ViewCommand command;
    defineOptions(app, command);
    return describeCommand("view", app, viewUsage());
}

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
    // Before any thread starts (the devices', the server's): a stop keeps unsaved edits.
    StopSignals stopSignals;
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
