// Writing an image with the one writer's options (core/atomic_file.h): what happens to a
// read-only file, where warnings go. image.h's writeImage is these with the defaults; this
// header is apart so that the many users of image.h need not see the writer's.
#pragma once

#include <filesystem>

#include "core/atomic_file.h"
#include "image/image.h"

namespace ray {

// writeImage (image.h) with `options`. Throws ImageError, FileWriteError, or OutputRefused
// for a target ray does not write (a folder, a read-only file without
// options.replaceReadOnly: core/atomic_file.h says which).
void writeImage(const Image& image, const std::filesystem::path& file, const WriteOptions& options);
void writeImage(const ByteImage& image, const std::filesystem::path& file, const WriteOptions& options);

}  // namespace ray
