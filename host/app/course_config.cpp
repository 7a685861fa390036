// The course's .ini configs (course_config.h).
#include "app/course_config.h"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "core/message_text.h"
#include "render/settings_table.h"
#include "scene/scene.h"

namespace fs = std::filesystem;

namespace ray {
namespace {

// A key's value as written, and its line.
struct Entry {
    std::string value;
    int line = 0;
};

// The keys the course's program reads, as "Section/key" (QSettings' names).
const char* const kKnownKeys[] = {
    "IO/scene",          "IO/output",          "Canvas/width",          "Canvas/height",
    "Feature/shadows",   "Feature/reflect",    "Feature/refract",       "Feature/texture",
    "Feature/texture-filter", "Feature/super-sample", "Feature/depthoffield", "Feature/mipmapping",
    "Feature/parallel",  "Feature/acceleration", "Feature/post-process",
    "Settings/maximum-recursive-depth", "Settings/samples-per-pixel", "Settings/super-sampler-pattern",
};

bool known(const std::string& key) {
    return std::any_of(std::begin(kKnownKeys), std::end(kKnownKeys), [&](const char* k) { return key == k; });
}

// Where the course's program reads a key written in the wrong section ("[Settings]"), or
// empty when it reads no key of that name.
std::string courseSectionOf(const std::string& name) {
    for (const char* k : kKnownKeys) {
        const std::string candidate = k;
        const size_t slash = candidate.find('/');
        if (candidate.substr(slash + 1) == name) return std::string("[").append(candidate, 0, slash) + "]";
    }
    return "";
}

std::string trimmed(const std::string& text) {
    const size_t first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos) return "";
    return text.substr(first, text.find_last_not_of(" \t\r\n") - first + 1);
}

class ConfigReader {
public:
    ConfigReader(const fs::path& file, bool strict) : file_(quotedForMessage(file.string())), strict_(strict) {}

    CourseConfig read(const std::string& text, const RenderSettings& base) {
        parseLines(text);
        CourseConfig config;
        config.settings = base;
        readIo(config);
        readCanvas(config.settings);
        readFeatures(config.settings);
        config.warnings = std::move(warnings_);
        return config;
    }

private:
    [[noreturn]] void fail(int line, const std::string& problem, const std::string& remedy) const {
        throw InputError(file_ + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": error: " + problem +
                         "; " + remedy);
    }

    void warn(int line, const std::string& message) {
        if (strict_) fail(line, message, "strict mode turns warnings into errors; remove or correct the key");
        warnings_.push_back(file_ + ":" + std::to_string(line) + ": warning: " + message);
    }

    // QSettings' .ini syntax: [Section] lines, key = value lines, comments from ';' or '#'.
    void parseLines(const std::string& text) {
        std::istringstream lines(text);
        std::string line, section;
        int number = 0;
        while (std::getline(lines, line)) {
            ++number;
            if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a byte-order mark
            line = trimmed(line);
            if (line.empty() || line[0] == ';' || line[0] == '#') continue;
            if (line.front() == '[') {
                if (line.back() != ']') fail(number, "a section line without its ']'", "write it as [Feature]");
                section = trimmed(line.substr(1, line.size() - 2));
                continue;
            }
            const size_t equals = line.find('=');
            if (equals == std::string::npos)
                fail(number, "'" + quotedForMessage(line) + "' is neither a [section] nor a key = value line",
                     "write key = value, or start the line with ; to make it a comment");
            const std::string name = trimmed(line.substr(0, equals));
            const std::string key = (section.empty() ? "General" : section) + "/" + name;
            std::string value = trimmed(line.substr(equals + 1));
            if (value.size() >= 2 && value.front() == '"' && value.back() == '"') value = value.substr(1, value.size() - 2);
            if (!known(key)) {
                const std::string where = courseSectionOf(name);
                warn(number, "unknown key '" + quotedForMessage(name) + "' in [" + quotedForMessage(section) + "]" +
                                 (where.empty() ? "" : " (the course's program reads it in " + where + ")") +
                                 "; it is ignored");
                continue;
            }
            auto [it, added] = entries_.try_emplace(key, Entry{value, number});
            if (!added) {
                warn(number, "'" + name + "' is given again (first on line " + std::to_string(it->second.line) +
                                 "); the last one counts");
                it->second = Entry{value, number};
            }
        }
    }

    const Entry* find(const char* key) const {
        auto it = entries_.find(key);
        return it == entries_.end() ? nullptr : &it->second;
    }

    void readIo(CourseConfig& config) {
        const Entry* scene = find("IO/scene");
        if (!scene || scene->value.empty())
            fail(0, "the config names no scene ([IO] scene)", "add scene = path/to/scene.json under [IO]");
        config.scene = scene->value;
        if (const Entry* output = find("IO/output")) config.output = output->value;
    }

    void readCanvas(RenderSettings& s) {
        if (const Entry* width = find("Canvas/width")) setWhole(s, "width", *width, "width");
        if (const Entry* height = find("Canvas/height")) setWhole(s, "height", *height, "height");
    }

    void readFeatures(RenderSettings& s) {
        s.shadows = flag("Feature/shadows");
        s.reflections = flag("Feature/reflect");
        s.refraction = flag("Feature/refract");
        s.textures = flag("Feature/texture");
        s.depthOfField = flag("Feature/depthoffield");
        flag("Feature/parallel");      // ray is always parallel
        flag("Feature/acceleration");  // and always uses its BVH
        if (flag("Feature/post-process"))
            warn(find("Feature/post-process")->line, "ray has no post-processing; post-process = true is ignored");
        s.maxDepth = 0;  // left out: 0, as the course's program reads it
        if (const Entry* depth = find("Settings/maximum-recursive-depth"))
            setWhole(s, "depth", *depth, "maximum-recursive-depth");
        readSampling(s);
        readTextureFilter(s);
    }

    void readSampling(RenderSettings& s) {
        if (const Entry* samples = find("Settings/samples-per-pixel")) setWhole(s, "samples", *samples, "samples-per-pixel");
        std::string pattern = "grid";
        if (const Entry* entry = find("Settings/super-sampler-pattern")) {
            pattern = entry->value;
            if (pattern != "grid" && pattern != "stratified" && pattern != "random" && pattern != "adaptive")
                fail(entry->line, "super-sampler-pattern must be \"grid\", \"stratified\", \"random\" or \"adaptive\", not '" +
                                      quotedForMessage(pattern) + "'",
                     "correct the value");
        }
        if (!flag("Feature/super-sample"))
            s.antialias = AntialiasMode::Off;
        else
            s.antialias = pattern == "adaptive" ? AntialiasMode::Adaptive : AntialiasMode::Stratified;
    }

    void readTextureFilter(RenderSettings& s) {
        const bool mipmapping = flag("Feature/mipmapping");
        const Entry* entry = find("Feature/texture-filter");
        if (!entry) return;  // ray's default, nearest, as the course's
        const std::string& name = entry->value;
        if (name == "nearest")
            s.textureFilter = TextureFilter::Nearest;
        else if (name == "bilinear")
            s.textureFilter = mipmapping ? TextureFilter::Trilinear : TextureFilter::Bilinear;
        else if (name == "trilinear") {
            if (!mipmapping)
                fail(entry->line, "trilinear filtering needs mip-mapping", "set mipmapping = true under [Feature]");
            s.textureFilter = TextureFilter::Trilinear;
        } else
            fail(entry->line, "texture-filter must be \"nearest\", \"bilinear\" or \"trilinear\", not '" +
                                  quotedForMessage(name) + "'",
                 "correct the value");
    }

    // true or false (1 or 0, in any case, as QSettings reads them); a key left out is false.
    bool flag(const char* key) const {
        const Entry* entry = find(key);
        if (!entry) return false;
        std::string value = entry->value;
        std::transform(value.begin(), value.end(), value.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        if (value == "true" || value == "1") return true;
        if (value == "false" || value == "0") return false;
        const std::string name = std::string(key).substr(std::string(key).find('/') + 1);
        fail(entry->line, name + " must be true or false, not '" + quotedForMessage(entry->value) + "'", "correct the value");
    }

    // A whole number into the setting `setting`, in the settings table's range.
    void setWhole(RenderSettings& s, const char* setting, const Entry& entry, const char* name) const {
        const SettingSpec& spec = *findSetting(setting);
        int64_t value = 0;
        const char* begin = entry.value.data();
        const char* end = begin + entry.value.size();
        auto [stop, ec] = std::from_chars(begin, end, value);
        if (ec != std::errc() || stop != end)
            fail(entry.line, std::string(name) + " must be a whole number, not '" + quotedForMessage(entry.value) + "'",
                 "correct the value");
        if (value < int64_t(spec.minimum) || value > int64_t(spec.maximum))
            fail(entry.line,
                 std::string(name) + " must be between " + formatWhole(spec.minimum) + " and " +
                     formatWhole(spec.maximum) + ", not " + entry.value,
                 "correct the value");
        setSetting(s, spec, value, name);
    }

    static std::string formatWhole(double value) { return std::to_string(int64_t(value)); }

    std::string file_;
    bool strict_;
    std::map<std::string, Entry> entries_;
    std::vector<std::string> warnings_;
};

}  // namespace

bool isCourseConfig(const fs::path& file) {
    std::string extension = file.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return extension == ".ini";
}

CourseConfig readCourseConfig(const std::string& text, const fs::path& file, const RenderSettings& base, bool strict) {
    return ConfigReader(file, strict).read(text, base);
}

CourseConfig loadCourseConfig(const fs::path& file, const RenderSettings& base, bool strict) {
    std::error_code ec;
    if (fs::is_directory(file, ec))
        throw InputError(quotedForMessage(file.string()) + ": error: this is a folder, not a config; give a .ini file");
    std::ifstream in(file, std::ios::binary);
    if (!in)
        throw InputError(quotedForMessage(file.string()) + ": error: cannot open the config; check the path");
    std::ostringstream text;
    text << in.rdbuf();
    return readCourseConfig(text.str(), file, base, strict);
}

}  // namespace ray
