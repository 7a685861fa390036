// libFuzzer target: the JSON bodies the viewer's page sends (POST /view, /edit, /save, /undo,
// /redo), each read as the viewer reads it (viewer/view_request.h, viewer/scene_editor.h),
// against a copy of scenes/shadows.xml in a scratch folder. The first byte picks the route,
// the rest is the body.
//
// A clean refusal is one of the viewer's own errors (what its routes turn into HTTP 400,
// 409). Anything else is a crash, and so are: a save outside the scratch folder; an edit
// that was taken, then saved, that loads back to another scene than the one the editor
// shows (what the user sees is what the file holds).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "fuzz_support.h"
#include "scene/scene_difference.h"
#include "scene/scene_loader.h"
#include "viewer/folder_files.h"
#include "viewer/scene_editor.h"
#include "viewer/view_request.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path& sceneFile() {
    static const fs::path file = [] {
        const fs::path folder = ray::fuzz::scratchFolder() / "viewer";
        fs::create_directories(folder);
        fs::copy_file(fs::path(RAY_SOURCE_DIR) / "scenes" / "shadows.xml", folder / "shadows.xml",
                      fs::copy_options::overwrite_existing);
        return folder / "shadows.xml";
    }();
    return file;
}

ray::SceneEditor& editor() {
    static ray::SceneEditor editor(sceneFile(), ray::LoadOptions{});
    return editor;
}

// What an edit the editor took saves as must load back to the scene the editor shows.
void checkSavedAsShown() {
    const fs::path copy = sceneFile().parent_path() / "check.xml";
    editor().save(std::string("check.xml"), true);
    const ray::Scene loaded = ray::loadScene(copy);
    const ray::SceneDifference difference = ray::compareScenes(loaded, *editor().scene());
    if (difference.any()) ray::fuzz::fail("an edit saves as another scene than the editor shows", "", "");
    fs::remove(copy);
}

void save(const std::string& body) {
    const ray::SaveRequest request = ray::saveRequestFrom(json::parse(body));
    const fs::path written = editor().save(request.as, request.replace);
    if (written.parent_path() != fs::canonical(sceneFile().parent_path()))
        ray::fuzz::fail("a save left the scene's folder", written.string());
    if (!fs::equivalent(written, sceneFile())) fs::remove(written);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const std::string body(reinterpret_cast<const char*>(data) + 1, size - 1);
    try {
        switch (data[0] % 5) {
            case 0: ray::parseView(body, ray::View{}); break;
            case 1:
                editor().edit(json::parse(body));
                checkSavedAsShown();
                break;
            case 2: save(body); break;
            case 3: editor().undo(); break;
            case 4: editor().redo(); break;
        }
    } catch (const std::invalid_argument&) {
        // EditError, BadFileName, SettingError and parseView's own: HTTP 400
    } catch (const ray::FileExists&) {  // HTTP 409
    } catch (const json::exception&) {  // not JSON as the route expects: HTTP 400
    }
    return 0;
}
