#include "viewer/view_request.h"

#include <cmath>
#include <stdexcept>
#include <string_view>
#include <variant>

#include "render/settings_table.h"

namespace ray {

using nlohmann::json;

namespace {

Vec3 vec3From(const json& j, const char* name) {
    if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
        throw std::invalid_argument(std::string(name) + " must be [x, y, z], three numbers");
    Vec3 v{j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) || length(v) > 1e9)
        throw std::invalid_argument(std::string(name) + " must be finite and within 10^9 of the origin");
    return v;
}

int intIn(const json& j, const char* key, int lo, int hi, int fallback) {
    if (!j.contains(key)) return fallback;
    const json& value = j.at(key);
    const std::string range = " from " + std::to_string(lo) + " to " + std::to_string(hi);
    if (!value.is_number_integer()) throw std::invalid_argument(std::string(key) + " must be a whole number" + range);
    const int64_t v = value.get<int64_t>();
    if (v < lo || v > hi) throw std::invalid_argument(std::string(key) + " must be" + range + ", not " + std::to_string(v));
    return v;
}

json vecJson(const Vec3& v) { return json::array({v.x, v.y, v.z}); }

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

std::string antialiasName(AntialiasMode mode) {
    RenderSettings settings;
    settings.antialias = mode;
    return std::get<std::string>(settingValue(settings, *findSetting("aa")));
}

}  // namespace

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

View parseView(const std::string& body, const View& current) {
    json j = json::parse(body);
    if (!j.is_object()) throw std::invalid_argument("a view is a JSON object of the fields to change");
    View view = current;
    if (j.contains("position")) view.camera.position = vec3From(j["position"], "position");
    if (j.contains("look")) view.camera.look = vec3From(j["look"], "look");
    if (j.contains("up")) view.camera.up = vec3From(j["up"], "up");
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

json frameKindJson(const FrameKind& kind) {
    return {{"view", kind.view}, {"scene", kind.scene}, {"aa", antialiasName(kind.antialias)}, {"final", kind.final},
            {"divisor", kind.divisor}};
}

std::string jsonText(const json& value) {
    return value.dump(-1, ' ', false, json::error_handler_t::replace);
}

json viewJson(const View& view) {
    json state{{"position", vecJson(view.camera.position)}, {"look", vecJson(view.camera.look)},
               {"up", vecJson(view.camera.up)},         {"height_angle", view.camera.heightAngleDegrees},
               {"width", view.settings.width},
               {"height", view.settings.height},        {"depth", view.settings.maxDepth},
               {"dof", dofControl(view.settings)}};
    for (const SettingSpec& spec : renderSettingsTable())
        if (!viewerOwnControl(spec.name)) state[std::string(spec.name)] = settingJson(view.settings, spec);
    return state;
}

}  // namespace ray
