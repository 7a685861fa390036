// The render settings, declared once (settings_table.cpp): each RenderSettings member a
// front end can set is one entry with its name, range or choices and help. The command
// line's options (app/cli.h), the public API's checks and conversion (api/), the Python
// module's keywords (through the API), the viewer's controls and --stats-json all walk
// this table. Adding a setting: a RenderSettings member, one entry, and its use in the
// renderers (plus its field in the public include/ray/renderer.h Settings).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "render/render_settings.h"

namespace ray {

// What a setting holds; read off the type of its RenderSettings member.
enum class SettingKind {
    Integer,  // int, uint32_t
    Number,   // double
    Switch,   // bool
    Choice,   // an enum, by name
};

struct SettingChoice {
    std::string_view name;  // as every front end spells it: "stratified"
    int value;              // the enum's value
    std::string_view note;  // what it means, for --help; may be empty
};

// The RenderSettings member an entry reads and writes.
using SettingField = std::variant<int RenderSettings::*, uint32_t RenderSettings::*, double RenderSettings::*,
                                  bool RenderSettings::*, AntialiasMode RenderSettings::*,
                                  DofMode RenderSettings::*, TextureFilter RenderSettings::*>;

struct SettingSpec {
    // The Python keyword and JSON key ("area_samples"); the command line's option is the
    // same with dashes (--area-samples), --no-<name> for a switch that is on by default.
    std::string_view name;
    SettingField field;
    std::string_view help;  // one phrase, for --help and the viewer's tooltips
    double minimum = 0, maximum = 0;     // Integer and Number, both included
    std::vector<SettingChoice> choices = {};  // Choice
    std::string_view valueName = "";     // the value in --help: "--samples N"
    std::string_view optionOverride = "";  // an option not spelled from the name (--dof for dof_mode)
    // The course's positionals ([<width> <height>] [<depth>]) rather than options.
    bool positional = false;

    SettingKind kind() const;
    std::string optionName() const;
    // The choice named `name`, or null.
    const SettingChoice* choiceNamed(std::string_view choiceName) const;
};

// Every render setting, in the order --help and the viewer list them.
const std::vector<SettingSpec>& renderSettingsTable();
// The entry named `name` ("area_samples"), or null.
const SettingSpec* findSetting(std::string_view name);

// A setting's value as front ends pass it: Integer int64_t, Number double, Switch bool,
// Choice its name (a std::string) or its enum's value (an int64_t).
using SettingValue = std::variant<bool, int64_t, double, std::string>;

// A value refused: of another kind, out of range, no such choice. The message names the
// setting as the caller labelled it and says what it takes.
struct SettingError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

// The setting's value in `settings` (a Choice as its name).
SettingValue settingValue(const RenderSettings& settings, const SettingSpec& spec);
// Sets it after checking kind, range and choice. Throws SettingError naming `label`.
void setSetting(RenderSettings& settings, const SettingSpec& spec, const SettingValue& value, std::string_view label);
// Every Integer and Number setting in its range; throws SettingError naming the first
// one out of it by its name.
void checkSettingRanges(const RenderSettings& settings);

// The choices' names: "off, course, stratified or adaptive" with lastSeparator " or ".
std::string choiceNames(const SettingSpec& spec, std::string_view separator, std::string_view lastSeparator);

}  // namespace ray
