#include "api/error_translation.h"

#include <new>
#include <regex>

#include "image/image.h"
#include "ray/errors.h"
#include "render/device_error.h"
#include "scene/scene.h"

namespace ray::api::detail {

namespace {

// Internal input messages start "<file>:<line>: error: " or, without a line (a file that
// cannot be opened), "<file>: error: ".
InputError inputErrorFrom(const std::string& message) {
    static const std::regex withLine(R"(^(.*?):(\d+): (error|warning))");
    static const std::regex withoutLine(R"(^(.*?): (error|warning))");
    std::smatch match;
    if (std::regex_search(message, match, withLine)) return InputError(message, match[1], std::stoi(match[2]));
    if (std::regex_search(message, match, withoutLine)) return InputError(message, match[1], 0);
    return InputError(message, "", 0);
}

}  // namespace

void rethrowAsPublic() {
    try {
        throw;
    } catch (const Error&) {
        throw;  // already public
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const ray::InputError& e) {
        throw inputErrorFrom(e.what());
    } catch (const ray::DeviceError& e) {
        throw DeviceError(e.what());
    } catch (const ray::ImageError& e) {
        throw DeviceError(e.what());
    } catch (const std::exception& e) {
        throw DeviceError(e.what());
    }
}

}  // namespace ray::api::detail
