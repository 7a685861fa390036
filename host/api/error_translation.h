// The internal exceptions (scene/scene.h InputError, render/device_error.h DeviceError,
// image/image.h ImageError) as the public API's (include/ray/errors.h).
#pragma once

#include <exception>
#include <utility>

// Not part of libray.so's interface (only ray::api is: cmake/libray.map).
#pragma GCC visibility push(hidden)
namespace ray::api::detail {

// Rethrows the exception being handled as its public type. Call inside a catch block.
[[noreturn]] void rethrowAsPublic();

// Runs f, turning internal exceptions into public ones.
template <class F>
auto translatingErrors(F&& f) -> decltype(f()) {
    try {
        return std::forward<F>(f)();
    } catch (...) {
        rethrowAsPublic();
    }
}

}  // namespace ray::api::detail
#pragma GCC visibility pop
