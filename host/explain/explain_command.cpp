#include "explain/explain_command.h"

#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <map>

#include "app/cli.h"
#include "core/atomic_file.h"
#include "explain/explanation_report.h"
#include "scene/file_search.h"
#include "scene/scene_loader.h"

namespace ray {

namespace {

struct ExplainOptions {
    std::filesystem::path scene;
    int x = 0, y = 0;
    std::vector<int> sizeAndDepth;  // [w h] [depth]
    std::filesystem::path json;
    std::vector<std::filesystem::path> searchPaths;
    bool noShadows = false, noReflections = false, noRefraction = false, noTextures = false, noDof = false;
    RenderSettings settings;
};

const std::map<std::string, AntialiasMode> kAntialiasModes{{"off", AntialiasMode::Off},
                                                           {"course", AntialiasMode::Course},
                                                           {"stratified", AntialiasMode::Stratified},
                                                           {"adaptive", AntialiasMode::Adaptive}};
const std::map<std::string, DofMode> kDofModes{{"course", DofMode::Course}, {"disk", DofMode::Disk}};

void defineOptions(CLI::App& app, ExplainOptions& o) {
    app.add_option("scene", o.scene, "the scenefile")->required();
    app.add_option("x", o.x, "pixel column, 0 at the left")->required();
    app.add_option("y", o.y, "pixel row, 0 at the top")->required();
    app.add_option("size_and_depth", o.sizeAndDepth, "[width height] [depth] as for ray (default 1024 768 4)")
        ->expected(0, 3);
    app.add_option("--json", o.json, "also write the tree as JSON to FILE");
    app.add_option("--aa", o.settings.antialias, "antialiasing: off | course | stratified | adaptive")
        ->transform(CLI::CheckedTransformer(kAntialiasModes, CLI::ignore_case));
    app.add_option("--samples", o.settings.samples, "samples a pixel (stratified, adaptive)")
        ->check(CLI::Range(1, kMaxSamples));
    app.add_option("--seed", o.settings.seed, "noise pattern of the stochastic modes");
    app.add_option("--area-samples", o.settings.areaSamples, "point samples per area light")
        ->check(CLI::Range(1, kMaxAreaSamples));
    app.add_option("--shutter", o.settings.shutter, "motion blur: fraction of the motion")->check(CLI::Range(0.0, 1.0));
    app.add_option("--search-path", o.searchPaths, "folders to look for textures and meshes in");
    app.add_flag("--no-shadows", o.noShadows);
    app.add_flag("--no-reflections", o.noReflections);
    app.add_flag("--no-refraction", o.noRefraction);
    app.add_flag("--no-textures", o.noTextures);
    app.add_flag("--no-dof", o.noDof);
    app.add_option("--dof", o.settings.dofMode, "depth of field: course (5x5 lens grid) | disk (random lens point)")
        ->transform(CLI::CheckedTransformer(kDofModes, CLI::ignore_case));
    app.add_flag("--fresnel", o.settings.fresnel, "weight transparent surfaces' branches by exact Fresnel");
    app.add_flag("--course-meshes", o.settings.courseMeshes,
                 "mesh hits by the course's distance t·|M⁻¹d|, placed there, face normals");
}

// The positional [w h] [depth] and the switches into the settings; throws UsageError.
void finishSettings(ExplainOptions& o) {
    RenderSettings& s = o.settings;
    const std::vector<int>& v = o.sizeAndDepth;
    if (v.size() == 1) s.maxDepth = v[0];
    if (v.size() >= 2) {
        s.width = v[0];
        s.height = v[1];
    }
    if (v.size() == 3) s.maxDepth = v[2];
    if (s.width < 1 || s.height < 1 || s.width > kMaxImageSide || s.height > kMaxImageSide)
        throw UsageError("width and height must be 1.." + std::to_string(kMaxImageSide));
    if (s.maxDepth < 0 || s.maxDepth > kMaxDepth) throw UsageError("depth must be 0.." + std::to_string(kMaxDepth));
    if (o.x < 0 || o.y < 0 || o.x >= s.width || o.y >= s.height)
        throw UsageError("pixel (" + std::to_string(o.x) + ", " + std::to_string(o.y) + ") is outside the " +
                         std::to_string(s.width) + "x" + std::to_string(s.height) + " image");
    s.shadows = !o.noShadows;
    s.reflections = !o.noReflections;
    s.refraction = !o.noRefraction;
    s.textures = !o.noTextures;
    s.depthOfField = !o.noDof;
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

int runExplainCommand(const std::vector<std::string>& args) {
    CLI::App app{"ray explain: the tree of rays of one pixel, traced by the reference renderer", "ray explain"};
    ExplainOptions options;
    options.settings.width = 1024;
    options.settings.height = 768;
    defineOptions(app, options);
    try {
        std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
        app.parse(reversed);
        finishSettings(options);
        return explain(options);
    } catch (const CLI::CallForHelp&) {
        std::cout << app.help();
        return 0;
    } catch (const CLI::ParseError& e) {
        std::cerr << "ray explain: " << e.what() << "\n(see ray explain --help)\n";
        return 2;
    } catch (const UsageError& e) {
        std::cerr << "ray explain: " << e.what() << "\n(see ray explain --help)\n";
        return 2;
    } catch (const InputError& e) {
        std::cerr << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "ray explain: " << e.what() << "\n";
        return 3;
    }
}

}  // namespace ray
