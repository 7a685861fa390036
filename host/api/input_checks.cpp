#include "api/input_checks.h"

#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "api/camera_conversion.h"
#include "api/settings_conversion.h"
#include "image/decode_limits.h"
#include "render/render_settings.h"
#include "scene/parameter_rules.h"

namespace ray::api::detail {

namespace {

[[noreturn]] void badInput(const std::string& what) { throw InputError("error: " + what, "", 0); }

template <class Value>
void checkRule(std::string_view name, const Value& value, const NumberRule& rule) {
    if (std::optional<RuleBroken> broken = brokenRule(name, value, rule)) badInput(broken->sentence());
}

}  // namespace

void checkFinite(const char* name, const Vec3& values) { checkRule(name, toInternal(values), rules::kFinite); }
void checkFinite(const char* name, double value) { checkRule(name, value, rules::kFinite); }

static_assert(ray::api::kMaxTexturePixels == ray::kMaxTexturePixels, "the public budget is the decoders'");
static_assert(ray::api::kMaxImageSide == ray::kMaxImageSide, "the public largest side is the renderers'");

namespace {

// Both sides positive, at most maxSide each and maxPixels together; `budget` says the limit
// in the message.
void checkImageSize(const std::string& what, int64_t width, int64_t height, int64_t maxSide, uint64_t maxPixels,
                    const std::string& budget, const std::string& file) {
    const std::string size = std::to_string(width) + " x " + std::to_string(height);
    const std::string place = file.empty() ? "" : file + ": ";
    if (width <= 0 || height <= 0)
        throw InputError(place + "error: " + what + " of " + size + " has no pixels; give at least 1 x 1", file, 0);
    if (width > maxSide || height > maxSide || uint64_t(width) * uint64_t(height) > maxPixels)
        throw InputError(place + "error: " + what + " of " + size + " pixels is more than " + budget +
                             "; scale it down",
                         file, 0);
}

}  // namespace

ray::WriteOptions writeOptionsOf(const WriteOptions& options) {
    ray::WriteOptions write;
    write.replaceReadOnly = options.replaceReadOnly;
    write.replaceReadOnlyHint = "WriteOptions::replaceReadOnly (Python: replace_read_only=True)";
    return write;
}

void checkTextureSize(int64_t width, int64_t height) {
    checkImageSize("a texture", width, height, int64_t(kMaxTexturePixels), kMaxTexturePixels,
                   std::string("a texture's budget of ") + kTextureBudgetText + " pixels, as for a texture file", "");
}

void checkImageToSaveSize(int64_t width, int64_t height, const std::string& file) {
    const int64_t side = kMaxImageSide;
    checkImageSize("an image", width, height, side, uint64_t(side) * uint64_t(side),
                   "the largest image ray renders, " + std::to_string(side) + " x " + std::to_string(side), file);
}

// The conversion checks each value against the table as it goes.
void checkSettings(const Settings& s) { toInternal(s); }

}  // namespace ray::api::detail
