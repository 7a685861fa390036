#include "viewer/view_command.h"

#include <CLI/CLI.hpp>
#include <iostream>

#include "app/cli.h"
#include "app/command_module_abi.h"
#include "app/render_command.h"
#include "scene/file_search.h"
#include "opencl/opencl_device.h"
#include "render/renderer.h"
#include "viewer/opencl_frame_source.h"
#include "viewer/viewer_server.h"

namespace ray {

int runViewCommand(const std::vector<std::string>& args) {
    CLI::App app{"ray view: a live viewer in the browser, served on 127.0.0.1", "ray view"};
    ViewerOptions options;
    options.settings.width = 640;
    options.settings.height = 480;
    options.settings.antialias = AntialiasMode::Off;  // interactive: one sample first
    std::vector<std::filesystem::path> searchPaths;
    std::string device = "auto";
    app.add_option("scene", options.scene, "the scenefile (watched: saving it reloads)")->required();
    app.add_option("--port", options.port, "TCP port (0: any free one; default 8123)")->check(CLI::Range(0, 65535));
    app.add_option("--bind", options.address,
                   "address to listen on (default 127.0.0.1; anything else exposes the viewer to the network)");
    app.add_option("--width", options.settings.width)->check(CLI::Range(kMinViewSide, kMaxViewSide));
    app.add_option("--height", options.settings.height)->check(CLI::Range(kMinViewSide, kMaxViewSide));
    app.add_option("--depth", options.settings.maxDepth)->check(CLI::Range(0, kMaxViewDepth));
    app.add_option("--device", device,
                   "auto|cpu|gpu|all|<index>|<list>: OpenCL devices, the scene packed once; ref: the reference renderer")
        ->check([](const std::string& value) { return isDeviceSelection(value) ? "" : "not a device selection"; });
    app.add_option("--search-path", searchPaths, "folders to look for textures and meshes in");
    try {
        app.parse(std::vector<std::string>(args.rbegin(), args.rend()));
    } catch (const CLI::CallForHelp&) {
        std::cout << app.help();
        return 0;
    } catch (const CLI::ParseError& e) {
        std::cerr << "ray view: " << e.what() << "\n(see ray view --help)\n";
        return 2;
    }
    if (options.address != "127.0.0.1" && options.address != "localhost")
        std::cerr << "ray view: warning: listening on " << options.address
                  << ", not only this machine: anyone who can reach it can use the viewer\n";
    options.load.searchPaths = searchPaths;
    for (auto& p : searchPathsFromEnvironment()) options.load.searchPaths.push_back(p);
    options.load.warn = [](const std::string& message) { std::cerr << message << "\n"; };
    options.onListening = [&](int port) {
        std::cout << "ray view: http://" << options.address << ":" << port << "/" << std::endl;
    };
    try {
        std::unique_ptr<FrameSource> source;
        if (isReferenceDevice(device))
            source = std::make_unique<ReferenceFrameSource>();
        else
            source = std::make_unique<OpenClFrameSource>(selectOpenClDevices(device));
        runViewer(options, std::move(source));
        return 0;
    } catch (const InputError& e) {
        std::cerr << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "ray view: " << e.what() << "\n";
        return 3;
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
