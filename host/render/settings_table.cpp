#include "render/settings_table.h"

#include "scene/parameter_rules.h"

#include <cmath>
#include <sstream>
#include <type_traits>

namespace ray {

namespace {

// The table. Defaults are not restated: every front end reads them off RenderSettings{}.
// Help phrases are written for `ray --help` (the line after the option's name); the
// default, the range and the choices are added to them where they are shown.
std::vector<SettingSpec> makeTable() {
    using S = RenderSettings;
    return {
        {.name = "width", .field = &S::width, .help = "image width in pixels", .minimum = 1,
         .maximum = kMaxImageSide, .positional = true},
        {.name = "height", .field = &S::height, .help = "image height in pixels", .minimum = 1,
         .maximum = kMaxImageSide, .positional = true},
        {.name = "depth", .field = &S::maxDepth, .help = "recursion depth: bounces after the camera ray",
         .minimum = 0, .maximum = kMaxDepth, .positional = true},
        {.name = "aa", .field = &S::antialias, .help = "antialiasing",
         .choices = {{"off", int(AntialiasMode::Off), "one sample at the pixel centre"},
                     {"course", int(AntialiasMode::Course), "the course's adaptive 4..64 samples"},
                     {"stratified", int(AntialiasMode::Stratified), "--samples jittered samples"},
                     {"adaptive", int(AntialiasMode::Adaptive), "more samples where neighbours differ"}},
         .valueName = "MODE"},
        {.name = "samples", .field = &S::samples, .help = "samples per pixel for stratified/adaptive",
         .minimum = 1, .maximum = kMaxSamples, .valueName = "N"},
        {.name = "seed", .field = &S::seed, .help = "seed of the stochastic sampling", .minimum = 0,
         .maximum = 4294967295.0, .valueName = "N"},
        {.name = "area_samples", .field = &S::areaSamples,
         .help = "point samples per area light, a jittered k×k grid with k = floor(sqrt(N))", .minimum = 1,
         .maximum = kMaxAreaSamples, .valueName = "N"},
        {.name = "shutter", .field = &S::shutter,
         .help = "motion blur: the shutter stays open over the fraction T of the scene's <motion>, 1 the whole "
                 "motion, 0 the scene at rest; every camera sample takes its own time",
         .minimum = 0, .maximum = 1, .valueName = "T"},
        {.name = "threshold", .field = &S::weightThreshold,
         .help = "stop a reflected/refracted branch whose weight is below T in every channel",
         .minimum = 0, .maximum = 1, .valueName = "T"},
        {.name = "shadows", .field = &S::shadows, .help = "no shadow rays: every light reaches every point"},
        {.name = "reflections", .field = &S::reflections, .help = "no reflected rays"},
        {.name = "refraction", .field = &S::refraction, .help = "no refracted (transmitted) rays"},
        {.name = "textures", .field = &S::textures, .help = "no textures: the materials' own colors"},
        {.name = "dof", .field = &S::depthOfField, .help = "no depth of field: every camera is a pinhole"},
        {.name = "dof_mode", .field = &S::dofMode, .help = "depth of field for cameras with an aperture",
         .choices = {{"course", int(DofMode::Course),
                      "each sample averages 25 rays from a 5x5 grid of lens points, as the course renders it"},
                     {"disk", int(DofMode::Disk),
                      "one random lens point a sample: a smooth blur with --aa stratified and many samples"}},
         .valueName = "MODE", .optionOverride = "--dof"},
        {.name = "fresnel", .field = &S::fresnel,
         .help = "weight the reflection and transmission of transparent objects by exact Fresnel, reflections "
                 "kept inside the object, as SPEC §4 has it"},
        {.name = "course_meshes", .field = &S::courseMeshes,
         .help = "measure mesh hits as the course's solution did: distance along the normalized object-space ray "
                 "(t·|M⁻¹d|), hit point placed there, face normals; docs/conventions.md"},
        {.name = "texture_filter", .field = &S::textureFilter, .help = "texture filtering",
         .choices = {{"nearest", int(TextureFilter::Nearest), "as the course"},
                     {"bilinear", int(TextureFilter::Bilinear), ""},
                     {"trilinear", int(TextureFilter::Trilinear), ""},
                     {"course", int(TextureFilter::Course),
                      "bilinear with texel corners at integers, as the course's renders made with its texture "
                      "filter on"}},
         .valueName = "F"},
    };
}

template <class Member>
constexpr SettingKind kindOf() {
    if constexpr (std::is_same_v<Member, bool>) return SettingKind::Switch;
    else if constexpr (std::is_enum_v<Member>) return SettingKind::Choice;
    else if constexpr (std::is_floating_point_v<Member>) return SettingKind::Number;
    else return SettingKind::Integer;
}

const char* kindWord(SettingKind kind) {
    switch (kind) {
        case SettingKind::Integer: return "a whole number";
        case SettingKind::Number: return "a number";
        case SettingKind::Switch: return "true or false";
        case SettingKind::Choice: return "a name";
    }
    return "";
}

[[noreturn]] void refuseKind(const SettingSpec& spec, std::string_view label) {
    throw SettingError(std::string(label) + " must be " + kindWord(spec.kind()));
}

void checkRange(const SettingSpec& spec, double value, std::string_view label) {
    if (!(value >= spec.minimum && value <= spec.maximum))
        throw SettingError(std::string(label) + " must be between " + formatNumber(spec.minimum) + " and " +
                           formatNumber(spec.maximum) + ", not " + formatNumber(value));
}

double numberFrom(const SettingSpec& spec, const SettingValue& value, std::string_view label) {
    if (const int64_t* whole = std::get_if<int64_t>(&value)) return double(*whole);
    const double* real = std::get_if<double>(&value);
    if (!real || spec.kind() == SettingKind::Integer) refuseKind(spec, label);
    return *real;
}

int choiceFrom(const SettingSpec& spec, const SettingValue& value, std::string_view label) {
    if (const std::string* name = std::get_if<std::string>(&value)) {
        if (const SettingChoice* choice = spec.choiceNamed(*name)) return choice->value;
        throw SettingError(std::string(label) + " must be one of " + choiceNames(spec, ", ", ", ") + ", not '" +
                           *name + "'");
    }
    if (const int64_t* index = std::get_if<int64_t>(&value))
        for (const SettingChoice& choice : spec.choices)
            if (choice.value == *index) return choice.value;
    refuseKind(spec, label);
}

}  // namespace

SettingKind SettingSpec::kind() const {
    return std::visit([](auto member) { return kindOf<std::remove_reference_t<decltype(RenderSettings{}.*member)>>(); },
                      field);
}

std::string SettingSpec::optionName() const {
    if (!optionOverride.empty()) return std::string(optionOverride);
    std::string option(name);
    for (char& c : option)
        if (c == '_') c = '-';
    // A switch names the change from the default: --no-shadows, --fresnel.
    if (kind() == SettingKind::Switch && std::get<bool RenderSettings::*>(field) != nullptr &&
        RenderSettings{}.*std::get<bool RenderSettings::*>(field))
        return "--no-" + option;
    return "--" + option;
}

const SettingChoice* SettingSpec::choiceNamed(std::string_view choiceName) const {
    for (const SettingChoice& choice : choices)
        if (choice.name == choiceName) return &choice;
    return nullptr;
}

const std::vector<SettingSpec>& renderSettingsTable() {
    static const std::vector<SettingSpec> table = makeTable();
    return table;
}

const SettingSpec* findSetting(std::string_view name) {
    for (const SettingSpec& spec : renderSettingsTable())
        if (spec.name == name) return &spec;
    return nullptr;
}

SettingValue settingValue(const RenderSettings& settings, const SettingSpec& spec) {
    return std::visit(
        [&](auto member) -> SettingValue {
            const auto value = settings.*member;
            using Member = std::remove_const_t<decltype(value)>;
            if constexpr (std::is_same_v<Member, bool>) return value;
            else if constexpr (std::is_enum_v<Member>) {
                const SettingChoice* named = nullptr;
                for (const SettingChoice& choice : spec.choices)
                    if (choice.value == int(value)) named = &choice;
                return named ? std::string(named->name) : std::string();
            } else if constexpr (std::is_floating_point_v<Member>) return double(value);
            else return int64_t(value);
        },
        spec.field);
}

void setSetting(RenderSettings& settings, const SettingSpec& spec, const SettingValue& value, std::string_view label) {
    std::visit(
        [&](auto member) {
            auto& target = settings.*member;
            using Member = std::remove_reference_t<decltype(target)>;
            if constexpr (std::is_same_v<Member, bool>) {
                const bool* on = std::get_if<bool>(&value);
                if (!on) refuseKind(spec, label);
                target = *on;
            } else if constexpr (std::is_enum_v<Member>) {
                target = Member(choiceFrom(spec, value, label));
            } else {
                const double number = numberFrom(spec, value, label);
                checkRange(spec, number, label);
                target = Member(number);
            }
        },
        spec.field);
}

void checkSettingRanges(const RenderSettings& settings) {
    for (const SettingSpec& spec : renderSettingsTable()) {
        const SettingKind kind = spec.kind();
        if (kind != SettingKind::Integer && kind != SettingKind::Number) continue;
        const SettingValue value = settingValue(settings, spec);
        checkRange(spec, kind == SettingKind::Integer ? double(std::get<int64_t>(value)) : std::get<double>(value),
                   spec.name);
    }
}

std::string choiceNames(const SettingSpec& spec, std::string_view separator, std::string_view lastSeparator) {
    std::string names;
    for (size_t i = 0; i < spec.choices.size(); ++i) {
        if (i > 0) names += i + 1 == spec.choices.size() ? lastSeparator : separator;
        names += spec.choices[i].name;
    }
    return names;
}

}  // namespace ray
