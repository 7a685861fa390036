#include "api/settings_conversion.h"

#include <type_traits>

#include "render/settings_table.h"

namespace ray::api {

namespace detail {

namespace {

// Each public field and the table entry it is: the one list of api::Settings' fields.
using PublicField = std::variant<int Settings::*, uint32_t Settings::*, double Settings::*, bool Settings::*,
                                 Antialias Settings::*, DofMode Settings::*, TextureFilter Settings::*>;
struct PublicSetting {
    std::string_view name;
    PublicField field;
};
const PublicSetting kPublicSettings[] = {
    {"width", &Settings::width},
    {"height", &Settings::height},
    {"depth", &Settings::depth},
    {"aa", &Settings::antialias},
    {"samples", &Settings::samples},
    {"seed", &Settings::seed},
    {"area_samples", &Settings::areaSamples},
    {"shutter", &Settings::shutter},
    {"threshold", &Settings::threshold},
    {"shadows", &Settings::shadows},
    {"reflections", &Settings::reflections},
    {"refraction", &Settings::refraction},
    {"textures", &Settings::textures},
    {"dof", &Settings::depthOfField},
    {"dof_mode", &Settings::dofMode},
    {"fresnel", &Settings::fresnel},
    {"course_meshes", &Settings::courseMeshes},
    {"texture_filter", &Settings::textureFilter},
};

[[noreturn]] void badSetting(const std::string& why) { throw InputError("error: " + why, "", 0); }

// A public field's value as the table takes it (an enum as its value: the public enums
// list their values in the internal ones' order).
ray::SettingValue publicValue(const Settings& settings, const PublicField& field) {
    return std::visit(
        [&](auto member) -> ray::SettingValue {
            const auto value = settings.*member;
            using Member = std::remove_const_t<decltype(value)>;
            if constexpr (std::is_same_v<Member, bool>) return value;
            else if constexpr (std::is_enum_v<Member>) return int64_t(value);
            else if constexpr (std::is_floating_point_v<Member>) return double(value);
            else return int64_t(value);
        },
        field);
}

void setPublicValue(Settings& settings, const PublicField& field, const SettingSpec& spec,
                    const ray::SettingValue& value) {
    std::visit(
        [&](auto member) {
            auto& target = settings.*member;
            using Member = std::remove_reference_t<decltype(target)>;
            if constexpr (std::is_same_v<Member, bool>) target = std::get<bool>(value);
            else if constexpr (std::is_enum_v<Member>) target = Member(spec.choiceNamed(std::get<std::string>(value))->value);
            else if constexpr (std::is_floating_point_v<Member>) target = Member(std::get<double>(value));
            else target = Member(std::get<int64_t>(value));
        },
        field);
}

const PublicSetting* publicSetting(std::string_view name) {
    for (const PublicSetting& setting : kPublicSettings)
        if (setting.name == name) return &setting;
    return nullptr;
}

}  // namespace

ray::RenderSettings toInternal(const Settings& settings) {
    ray::RenderSettings internal;
    try {
        for (const PublicSetting& setting : kPublicSettings)
            setSetting(internal, *findSetting(setting.name), publicValue(settings, setting.field), setting.name);
    } catch (const SettingError& e) {
        badSetting(e.what());
    }
    return internal;
}

Settings toPublic(const ray::RenderSettings& internal) {
    Settings settings;
    for (const PublicSetting& setting : kPublicSettings) {
        const SettingSpec& spec = *findSetting(setting.name);
        setPublicValue(settings, setting.field, spec, settingValue(internal, spec));
    }
    return settings;
}

std::vector<std::string> unmatchedSettingNames() {
    std::vector<std::string> unmatched;
    for (const SettingSpec& spec : renderSettingsTable())
        if (!publicSetting(spec.name)) unmatched.emplace_back(spec.name);
    for (const PublicSetting& setting : kPublicSettings)
        if (!findSetting(setting.name)) unmatched.emplace_back(setting.name);
    return unmatched;
}

}  // namespace detail

std::vector<SettingDescription> describeSettings() {
    std::vector<SettingDescription> descriptions;
    for (const SettingSpec& spec : renderSettingsTable()) {
        SettingDescription d;
        d.name = spec.name;
        d.kind = SettingDescription::Kind(int(spec.kind()));  // the same order
        d.minimum = spec.minimum;
        d.maximum = spec.maximum;
        for (const SettingChoice& choice : spec.choices) d.choices.emplace_back(choice.name);
        d.help = spec.help;
        descriptions.push_back(std::move(d));
    }
    return descriptions;
}

void setSetting(Settings& settings, const std::string& name, const SettingValue& value) {
    const SettingSpec* spec = findSetting(name);
    if (!spec) detail::badSetting("there is no setting '" + name + "'");
    // Through the internal settings, so that the table checks the value.
    ray::RenderSettings internal = detail::toInternal(settings);
    try {
        ray::setSetting(internal, *spec, value, name);
    } catch (const SettingError& e) {
        detail::badSetting(e.what());
    }
    settings = detail::toPublic(internal);
}

}  // namespace ray::api
