// Reading and writing images with OpenImageIO.
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <system_error>

#include "image/image.h"
#include "core/memory_limits.h"

namespace ray {
namespace fs = std::filesystem;

namespace {

std::string lowerExtension(const fs::path& file) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// A file beside the target, with the same extension so OpenImageIO picks the same format.
fs::path temporarySibling(const fs::path& file) {
    std::string name = ".";
    name += file.stem().string();
    name += ".tmp" + std::to_string(getpid());
    name += file.extension().string();
    fs::path tmp = file;
    tmp.replace_filename(name);
    return tmp;
}

// libpng allocates (and clears) a chunk's whole declared length before reading it, so a
// 1.6 KB PNG whose text chunk claims 1.9 GB took 10 s and 2 GB (found by
// fuzz_image_reader; tests/data/fuzz/image_reader/png_chunk_claims_2gb.png). No chunk can be longer
// than the file, so such a file is refused before OpenImageIO opens it.
void checkPngChunkLengths(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    unsigned char signature[8] = {};
    static const unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (!in.read(reinterpret_cast<char*>(signature), 8) || !std::equal(signature, signature + 8, kPngSignature)) return;
    std::error_code ec;
    const uint64_t fileSize = fs::file_size(file, ec);
    if (ec) return;
    uint64_t offset = 8;
    unsigned char header[8];
    while (in.read(reinterpret_cast<char*>(header), 8)) {
        const uint64_t length = uint64_t(header[0]) << 24 | uint64_t(header[1]) << 16 | uint64_t(header[2]) << 8 | header[3];
        const std::string type(reinterpret_cast<const char*>(header + 4), 4);
        if (offset + 12 + length > fileSize)
            throw ImageError(file.string() + ": corrupt PNG: its " + type + " chunk claims " + std::to_string(length) +
                             " bytes, more than the file holds");
        if (type == "IEND") return;
        offset += 12 + length;
        in.seekg(std::streamoff(offset));
    }
}

}  // namespace

Image readImage(const fs::path& file) {
    checkPngChunkLengths(file);
    auto input = OIIO::ImageInput::open(file.string());
    if (!input) throw ImageError(file.string() + ": cannot read image: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
        throw ImageError(file.string() + ": image has no pixels");
    // Refuse absurd sizes before allocating (a corrupt header can claim anything).
    constexpr int64_t kMaxPixels = int64_t(1) << 28;
    if (int64_t(spec.width) * spec.height > kMaxPixels)
        throw ImageError(file.string() + ": image is " + std::to_string(spec.width) + "x" +
                         std::to_string(spec.height) + ", larger than the 2^28-pixel limit");
    const int channels = spec.nchannels;
    // The decoded floats, then the RGB copy: estimated before either is allocated.
    const uint64_t bytes = uint64_t(spec.width) * uint64_t(spec.height) * uint64_t(channels + 3) * sizeof(float);
    if (auto shortfall = hostMemoryShortfall(bytes))
        throw ImageError(file.string() + ": a " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                         " image " + *shortfall);
    std::vector<float> pixels(size_t(spec.width) * size_t(spec.height) * size_t(channels));
    // Integer formats convert to [0, 1] as v / max, i.e. v/255 for 8-bit files.
    if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data()))
        throw ImageError(file.string() + ": cannot decode image: " + input->geterror());
    input->close();

    Image image(spec.width, spec.height);
    for (size_t p = 0, n = size_t(spec.width) * size_t(spec.height); p < n; ++p) {
        const float* src = &pixels[p * size_t(channels)];
        for (int c = 0; c < 3; ++c) image.rgb[p * 3 + size_t(c)] = channels >= 3 ? src[c] : src[0];
    }
    return image;
}

bool isFloatFormat(const fs::path& file) {
    std::string ext = lowerExtension(file);
    return ext == ".exr" || ext == ".hdr" || ext == ".pfm";
}

const char* const kOutputFormatAdvice = "use .png, .jpg, .tif, .ppm (8-bit) or .exr, .hdr (float)";

bool canWriteImageFormat(const fs::path& file) {
    return !file.extension().empty() && OIIO::ImageOutput::create(file.string()) != nullptr;
}

void writeImage(const Image& image, const fs::path& file) {
    if (image.empty()) throw ImageError(file.string() + ": refusing to write an empty image");
    fs::path tmp = temporarySibling(file);
    auto output = OIIO::ImageOutput::create(tmp.string());
    if (!output)
        throw ImageError(file.string() + ": cannot write the output format '" + file.extension().string() + "'; " +
                         kOutputFormatAdvice);

    const bool floats = isFloatFormat(file);
    OIIO::ImageSpec spec(image.width, image.height, 3, floats ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    std::vector<uint8_t> bytes;
    const void* data = image.rgb.data();
    if (!floats) {
        bytes.resize(image.rgb.size());
        for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = uint8_t(quantize8(image.rgb[i]));
        data = bytes.data();
    }
    bool ok = output->open(tmp.string(), spec) &&
              output->write_image(floats ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8, data) &&
              output->close();
    if (!ok) {
        std::string why = output->geterror();
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw ImageError(file.string() + ": cannot write image: " + why);
    }
    std::error_code ec;
    fs::rename(tmp, file, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw ImageError(file.string() + ": cannot write image: " + ec.message());
    }
}

}  // namespace ray
