// Checks of a file's header that run before a decoder sees the file, for decoders that
// allocate what a header claims before they read a pixel: a few bytes can otherwise claim
// gigabytes (both cases were found by fuzz_image_reader).
#pragma once

#include <filesystem>

namespace ray {

// libpng allocates (and clears) a chunk's whole declared length before reading it: a
// 1.6 KB PNG whose text chunk claimed 1.9 GB took 10 s and 2 GB. No chunk can be longer
// than the file, so such a file is refused. Does nothing to a file that is not a PNG.
void checkPngChunkLengths(const std::filesystem::path& file);

// OpenImageIO's GIF reader allocates a canvas of the logical screen's size (4 bytes a
// pixel) when it opens the file, before any frame is read: 24 bytes claiming 15,000²
// took 900 MB. The screen is held to a texture's budget (image/decode_limits.h). Does
// nothing to a file that is not a GIF.
void checkGifScreenSize(const std::filesystem::path& file);

}  // namespace ray
