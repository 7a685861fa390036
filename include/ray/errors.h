/// \file
/// The exceptions ray's public API throws. Every function of the API throws only these
/// (and std::bad_alloc); each message is complete and says what to do.
#pragma once

#include <stdexcept>
#include <string>

namespace ray::api {

/// The base of every ray error.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Bad input: a scene file or string that does not parse, a texture or mesh that cannot be
/// read, a setting out of range, a primitive naming a material that does not exist. The
/// message reads "scene.xml:12: error: what; what to do"; file() and line() give the place
/// (line 0 when the problem has none, such as a missing file).
class InputError : public Error {
public:
    /// An error with its complete message and its place (line 0: none).
    InputError(const std::string& message, std::string file, int line)
        : Error(message), file_(std::move(file)), line_(line) {}
    /// The file the error is in (a scene, texture or mesh), as it was named; empty when the
    /// error is in no file (a value out of range given in code).
    const std::string& file() const { return file_; }
    /// The line in file(), from 1; 0 when the problem has no line.
    int line() const { return line_; }

private:
    std::string file_;
    int line_;
};

/// The device failed: no OpenCL platform, a kernel that does not build, a scene or image
/// too big for the device, an output file that cannot be written. Try device "ref".
class DeviceError : public Error {
public:
    using Error::Error;
};

}  // namespace ray::api
