// The settings table (host/render/settings_table.h) and everything that reads it: the
// command line's options and help, the public API's Settings, its checks and by-name setter.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>
#include <string>

#include "api/settings_conversion.h"
#include "app/cli.h"
#include "render/render_stats.h"
#include "render/settings_table.h"
#include "scene/parameter_rules.h"

namespace {

using Catch::Matchers::Contains;
using ray::SettingKind;
using ray::SettingSpec;
using ray::SettingValue;

// A value of the setting other than its default, in its range or among its choices.
SettingValue otherValue(const SettingSpec& spec) {
    const SettingValue fallback = ray::settingValue(ray::RenderSettings{}, spec);
    switch (spec.kind()) {
        case SettingKind::Switch: return !std::get<bool>(fallback);
        case SettingKind::Integer:
            return std::get<int64_t>(fallback) == int64_t(spec.minimum) ? int64_t(spec.minimum) + 1 : int64_t(spec.minimum);
        case SettingKind::Number: return std::get<double>(fallback) == spec.minimum ? spec.maximum : spec.minimum;
        case SettingKind::Choice:
            for (const ray::SettingChoice& choice : spec.choices)
                if (choice.name != std::get<std::string>(fallback)) return std::string(choice.name);
    }
    FAIL("no other value for " << spec.name);
    return false;
}

// The value as the command line writes it.
std::string optionText(const SettingValue& value) {
    if (const int64_t* whole = std::get_if<int64_t>(&value)) return std::to_string(*whole);
    if (const double* real = std::get_if<double>(&value)) return ray::formatNumber(*real);
    return std::get<std::string>(value);
}

}  // namespace

TEST_CASE("settings table: names are unique, kinds and ranges are consistent", "[settings]") {
    const auto& table = ray::renderSettingsTable();
    REQUIRE(table.size() >= 18);
    for (const SettingSpec& spec : table) {
        INFO(spec.name);
        CHECK(ray::findSetting(spec.name) == &spec);
        CHECK_FALSE(spec.help.empty());
        const SettingKind kind = spec.kind();
        CHECK((kind == SettingKind::Choice) == !spec.choices.empty());
        if (kind == SettingKind::Integer || kind == SettingKind::Number) {
            CHECK(spec.minimum < spec.maximum);
            CHECK((spec.positional || !spec.valueName.empty()));
        }
        // The default is in range: the table's ranges hold RenderSettings' defaults.
        CHECK_NOTHROW(ray::setSetting(*std::make_unique<ray::RenderSettings>(), spec,
                                      ray::settingValue(ray::RenderSettings{}, spec), spec.name));
    }
    CHECK_NOTHROW(ray::checkSettingRanges(ray::RenderSettings{}));
    CHECK(ray::findSetting("no_such_setting") == nullptr);
}

TEST_CASE("settings table: values are checked with messages naming the setting", "[settings]") {
    ray::RenderSettings s;
    const SettingSpec& samples = *ray::findSetting("samples");
    CHECK_THROWS_WITH(ray::setSetting(s, samples, int64_t(0), "samples"), "samples must be between 1 and 4096, not 0");
    CHECK_THROWS_WITH(ray::setSetting(s, samples, 2.5, "samples"), "samples must be a whole number");
    CHECK_THROWS_WITH(ray::setSetting(s, *ray::findSetting("aa"), std::string("fast"), "aa"),
                      "aa must be one of off, course, stratified, adaptive, not 'fast'");
    CHECK_THROWS_WITH(ray::setSetting(s, *ray::findSetting("shadows"), int64_t(1), "shadows"),
                      "shadows must be true or false");
    ray::setSetting(s, *ray::findSetting("seed"), int64_t(4294967295), "seed");
    CHECK(s.seed == 4294967295u);
    ray::setSetting(s, *ray::findSetting("texture_filter"), std::string("course"), "texture_filter");
    CHECK(s.textureFilter == ray::TextureFilter::Course);
    s.shutter = 2;
    CHECK_THROWS_WITH(ray::checkSettingRanges(s), "shutter must be between 0 and 1, not 2");
}

TEST_CASE("settings table: every option is on the command line, in --help, and sets its setting", "[settings][cli]") {
    const std::string help = ray::renderSettingsHelp();
    for (const SettingSpec& spec : ray::renderSettingsTable()) {
        INFO(spec.name);
        if (spec.positional) {
            CHECK_THAT(ray::kUsageText, !Contains(spec.optionName() + " "));
            continue;
        }
        CHECK_THAT(help, Contains("  " + spec.optionName()));
        CHECK_THAT(ray::kUsageText, Contains("  " + spec.optionName()));
        const SettingValue value = otherValue(spec);
        std::vector<std::string> args = {"a.xml", spec.optionName()};
        if (spec.kind() != SettingKind::Switch) args.push_back(optionText(value));
        // --samples applies to the stochastic modes only.
        if (spec.name == "samples") args.insert(args.end(), {"--aa", "stratified"});
        const ray::RenderSettings parsed = ray::parseCommandLine(args).settings;
        CHECK(ray::settingValue(parsed, spec) == value);
    }
    CHECK_THAT(help, Contains("--aa MODE"));
    CHECK_THAT(help, Contains("stratified"));
    CHECK_THAT(help, Contains("course (default;"));
}

TEST_CASE("settings table: the public Settings has every setting, with the same defaults", "[settings][api]") {
    CHECK(ray::api::detail::unmatchedSettingNames().empty());
    const ray::RenderSettings converted = ray::api::detail::toInternal(ray::api::Settings{});
    for (const SettingSpec& spec : ray::renderSettingsTable()) {
        INFO(spec.name);
        CHECK(ray::settingValue(converted, spec) == ray::settingValue(ray::RenderSettings{}, spec));
    }
    std::vector<std::string> described;
    for (const ray::api::SettingDescription& d : ray::api::describeSettings()) described.push_back(d.name);
    CHECK(described.size() == ray::renderSettingsTable().size());
}

TEST_CASE("settings table: api::setSetting sets each setting by name, both ways", "[settings][api]") {
    for (const SettingSpec& spec : ray::renderSettingsTable()) {
        INFO(spec.name);
        ray::api::Settings settings;
        const SettingValue value = otherValue(spec);
        ray::api::setSetting(settings, std::string(spec.name), value);
        const ray::RenderSettings internal = ray::api::detail::toInternal(settings);
        CHECK(ray::settingValue(internal, spec) == value);
        CHECK(ray::settingValue(ray::api::detail::toInternal(ray::api::detail::toPublic(internal)), spec) == value);
    }
    ray::api::Settings settings;
    CHECK_THROWS_WITH(ray::api::setSetting(settings, "colour", true), "error: there is no setting 'colour'");
    CHECK_THROWS_WITH(ray::api::setSetting(settings, "depth", int64_t(65)), "error: depth must be between 0 and 64, not 65");
    settings.courseMeshes = true;
    CHECK(ray::api::detail::toInternal(settings).courseMeshes);
}

TEST_CASE("settings table: --stats-json echoes every setting by its name", "[settings][stats]") {
    ray::RenderSettings settings;
    settings.courseMeshes = true;
    settings.antialias = ray::AntialiasMode::Stratified;
    settings.seed = 7;
    settings.shutter = 0.5;
    const nlohmann::json json = nlohmann::json::parse(ray::statsToJson(ray::RenderStats{}, settings));
    const nlohmann::json& echoed = json.at("settings");
    CHECK(echoed.size() == ray::renderSettingsTable().size());
    CHECK(echoed.at("course_meshes") == true);
    CHECK(echoed.at("aa") == "stratified");
    CHECK(echoed.at("seed") == 7);
    CHECK(echoed.at("shutter") == 0.5);
    CHECK(echoed.at("width") == 1024);
    CHECK(json.contains("mrays_per_second"));  // the statistics stay where they were
}
