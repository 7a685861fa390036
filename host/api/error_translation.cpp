#include "api/error_translation.h"

#include <algorithm>
#include <new>
#include <optional>
#include <string>

#include "core/atomic_file.h"
#include "edit/edit_error.h"
#include "image/image.h"
#include "ray/errors.h"
#include "render/device_error.h"
#include "scene/scene.h"

namespace ray::api::detail {

namespace {

// Internal input messages start "<file>:<line>: error: " or, without a line (a file that
// cannot be opened), "<file>: error: " (or warning). Read by hand, in one pass: the message
// holds a file name from outside, of any length (std::regex recursed once a character and
// overflowed the stack on a name of 50,000).
// A JSON scene's messages add the column: "<file>:<line>:<column>: error: ".
InputError inputErrorFrom(const std::string& message) {
    size_t severity = std::string::npos;
    for (const char* marker : {": error", ": warning"}) severity = std::min(severity, message.find(marker));
    if (severity == std::string::npos) return InputError(message, "", 0);
    std::string place = message.substr(0, severity);
    // The number after the place's last colon, which is taken off it; nullopt when none.
    auto trailingNumber = [&place]() -> std::optional<int> {
        const size_t colon = place.rfind(':');
        const std::string digits = colon == std::string::npos ? "" : place.substr(colon + 1);
        if (digits.empty() || digits.size() > 9 ||
            !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
            return std::nullopt;
        place.resize(colon);
        return std::stoi(digits);
    };
    const std::optional<int> last = trailingNumber();
    if (!last) return InputError(message, place, 0);
    const std::string withoutColumn = place;
    if (const std::optional<int> line = trailingNumber()) return InputError(message, place, *line);
    return InputError(message, withoutColumn, *last);
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
    } catch (const ray::edit::EditError& e) {
        throw InputError(std::string("error: ") + e.what(), "", 0);
    } catch (const ray::OutputRefused& e) {  // a folder, a read-only file: the path given is the problem
        const std::string message = e.what();
        throw InputError(message, message.substr(0, message.find(": ")), 0);
    } catch (const ray::DeviceError& e) {
        throw DeviceError(e.what());
    } catch (const ray::ImageError& e) {
        throw DeviceError(e.what());
    } catch (const std::exception& e) {
        throw DeviceError(e.what());
    }
}

}  // namespace ray::api::detail
