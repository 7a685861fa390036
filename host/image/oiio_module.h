// OpenImageIO, loaded on first use: the formats that are neither PNG nor JPEG go through
// libray_oiio.so (oiio_plugin_abi.h), which ray opens with dlopen the first time it meets
// one. It is looked for as every module of ray is (core/module_loader.h); $RAY_OIIO_MODULE,
// a full path, replaces the search.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "image/image.h"

namespace ray {

// Loads the module now instead of at the first image that needs it, for a caller that times
// each image (the image fuzzer: loading OpenImageIO under AddressSanitizer's full unwinding
// takes seconds). Returns why it could not be loaded; empty when it was.
std::string preloadOiioModule();

// Decodes the file with the reader of `format` (an extension: "tga", "exr"), that reader
// alone; with none, OpenImageIO chooses by the name and the contents. Throws ImageError
// naming the file (also when the module cannot be found or loaded).
Image readImageWithOiio(const std::filesystem::path& file, std::string_view format = {});

// Whether OpenImageIO has a writer for the file's extension; false when the module is missing.
bool oiioCanWrite(const std::filesystem::path& file);

// Writes 3-channel samples (floats or bytes) to `file` in its extension's format. Throws
// ImageError naming `target` (the name the user asked for; `file` may be a temporary).
void writeImageWithOiio(const std::filesystem::path& file, const std::filesystem::path& target, int width, int height,
                        bool asFloat, const void* samples);

}  // namespace ray
