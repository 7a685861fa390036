#include "explain/explain_command.h"

#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "app/cli.h"
#include "core/atomic_file.h"
#include "explain/explanation_report.h"
#include "scene/file_search.h"
#include "scene/scene_loader.h"

namespace ray {

namespace {

const char* const kExplainIntro = R"(usage: ray explain <scene.xml> <x> <y> [<width> <height>] [<depth>] [options]

Prints the tree of rays of pixel (x, y) (0, 0 at the top left) as the reference renderer
traces it: every ray, hit, light term and branch not traced, with the term each number is
in the lighting equation. The image is as `ray` would render it: the same size and depth
arguments (the same defaults; a lone number after the pixel is the depth) and the same
render settings.

options:
  --json FILE              also write the tree as JSON to FILE
  -h, --help               this text
)";

std::string explainUsage() {
    return kExplainIntro + renderSettingsHelp() + "\nexit status: 0 success, 2 bad input or arguments\n";
}

struct ExplainOptions {
    std::filesystem::path scene;
    int x = 0, y = 0;
    std::vector<std::string> positionals;  // <scene.xml> <x> <y> [w h] [depth]
    std::filesystem::path json;
    std::vector<std::filesystem::path> searchPaths;
    RenderSettings settings;
    bool help = false;
};

void defineOptions(CLI::App& app, ExplainOptions& o) {
    app.set_help_flag();  // explainUsage() instead of CLI11's
    addSwitch(app, "-h,--help", [&] { o.help = true; });
    addValueOption(app, "--json", [&](const std::string& v) {
        if (v.empty()) throw UsageError("--json needs a file name");
        o.json = v;
    });
    addRenderSettingOptions(app, o.settings, o.searchPaths);
    app.add_option("positionals", o.positionals);
}

// The positionals into the options; throws UsageError.
void finishSettings(ExplainOptions& o) {
    const std::vector<std::string>& p = o.positionals;
    if (p.empty()) throw UsageError("no scene file given");
    if (p.size() < 3) throw UsageError("no pixel given: ray explain <scene.xml> <x> <y>");
    o.scene = p[0];
    RenderSettings& s = o.settings;
    applySizeAndDepth(std::vector<std::string>(p.begin() + 3, p.end()), s);
    o.x = parseInt(p[1], "the pixel's x", 0, s.width - 1);
    o.y = parseInt(p[2], "the pixel's y", 0, s.height - 1);
}

int explain(const ExplainOptions& o) {
    LoadOptions load;
    load.searchPaths = o.searchPaths;
    for (auto& p : searchPathsFromEnvironment()) load.searchPaths.push_back(p);
    load.loadImages = o.settings.textures;
    load.warn = [](const std::string& message) { std::cerr << message << "\n"; };
    Scene scene = loadScene(o.scene, load);
    PixelExplanation explanation = explainPixel(scene, o.settings, o.x, o.y);
    printExplanation(explanation, scene, std::cout);
    if (!o.json.empty()) writeFileAtomically(o.json, explanationJson(explanation, scene).dump(2) + "\n");
    return 0;
}

}  // namespace

CommandReference explainCommandReference() {
    CLI::App app{"ray explain", "ray explain"};
    ExplainOptions options;
    defineOptions(app, options);
    return describeCommand("explain", app, explainUsage());
}

int runExplainCommand(const std::vector<std::string>& args) {
    CLI::App app{"ray explain", "ray explain"};
    ExplainOptions options;
    defineOptions(app, options);
    try {
        parseArguments(app, args);
        if (options.help) {
            std::cout << explainUsage();
            return 0;
        }
        finishSettings(options);
    } catch (const UsageError& e) {
        std::cerr << "ray explain: " << e.what() << "\n(see ray explain --help)\n";
        return 2;
    }
    try {
        return explain(options);
    } catch (const InputError& e) {
        std::cerr << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "ray explain: " << e.what() << "\n";
        return 3;
    }
}

}  // namespace ray
