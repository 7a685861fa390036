// Reading and writing images with OpenImageIO.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <system_error>

#include "image/image.h"
#include "core/atomic_file.h"
#include "core/memory_limits.h"

namespace ray {
namespace fs = std::filesystem;

namespace {

std::string lowerExtension(const fs::path& file) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
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

// Only regular files are read: opening a FIFO blocks until someone writes to it, and a
// device such as /dev/zero never ends.
static void checkRegularFile(const fs::path& file) {
    std::error_code ec;
    const fs::file_status status = fs::status(file, ec);
    if (ec) throw ImageError(file.string() + ": cannot read image: " + ec.message());
    if (!fs::is_regular_file(status))
        throw ImageError(file.string() + ": cannot read image: not a regular file (" +
                         (fs::is_fifo(status) ? "a FIFO" : fs::is_directory(status) ? "a folder" : "a device or socket") +
                         "); give an image file");
}

Image readImage(const fs::path& file) {
    checkRegularFile(file);
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

namespace {

struct EncodedImage {
    OIIO::ImageSpec spec;
    OIIO::TypeDesc type;
    std::vector<uint8_t> bytes;  // 8-bit formats: the quantized values
    const void* data = nullptr;
};

// 8-bit formats get floor(255·clamp(c)) (SPEC §4); float formats the floats as they are.
EncodedImage pixelsToWrite(const Image& image, const fs::path& file) {
    EncodedImage e;
    const bool floats = isFloatFormat(file);
    e.type = floats ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
    e.spec = OIIO::ImageSpec(image.width, image.height, 3, e.type);
    e.data = image.rgb.data();
    if (!floats) {
        e.bytes.resize(image.rgb.size());
        for (size_t i = 0; i < e.bytes.size(); ++i) e.bytes[i] = uint8_t(quantize8(image.rgb[i]));
        e.data = e.bytes.data();
    }
    return e;
}

std::unique_ptr<OIIO::ImageOutput> createOutput(const fs::path& file) {
    auto output = OIIO::ImageOutput::create(file.string());
    if (!output)
        throw ImageError(file.string() + ": cannot write the output format '" + file.extension().string() + "'; " +
                         kOutputFormatAdvice);
    return output;
}

void encode(OIIO::ImageOutput& output, const std::string& name, const EncodedImage& e, const fs::path& file) {
    if (!(output.open(name, e.spec) && output.write_image(e.type, e.data) && output.close()))
        throw ImageError(file.string() + ": cannot encode image: " + output.geterror());
}

// Encodes into memory, so every byte that reaches the disk goes through the checked writes
// of writeFileAtomically: OpenImageIO's file writers do not all report a failed fwrite (a
// full disk once left a truncated PNG and "wrote out.png").
void writeThroughMemory(OIIO::ImageOutput& output, const EncodedImage& e, const fs::path& file) {
    std::vector<unsigned char> buffer;
    OIIO::Filesystem::IOVecOutput proxy(buffer);
    output.set_ioproxy(&proxy);
    encode(output, file.string(), e, file);
    writeFileAtomically(file, std::string_view(reinterpret_cast<const char*>(buffer.data()), buffer.size()));
}

// For a format whose writer cannot write to memory: it writes the temporary file, which is
// then decoded again, so a write the encoder did not notice failing cannot pass.
void writeThroughTemporaryPath(const EncodedImage& e, const fs::path& file) {
    writeFileAtomicallyVia(file, [&](const fs::path& tmp) {
        auto output = createOutput(file);
        encode(*output, tmp.string(), e, file);
        auto check = OIIO::ImageInput::open(tmp.string());
        std::vector<float> pixels(size_t(e.spec.width) * size_t(e.spec.height) * 3);
        if (!check || !check->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, pixels.data()))
            throw ImageError(file.string() + ": cannot write image: the written file does not decode (" +
                             (check ? check->geterror() : OIIO::geterror()) + "); is the disk full?");
    });
}

}  // namespace

void writeImage(const Image& image, const fs::path& file) {
    if (image.empty()) throw ImageError(file.string() + ": refusing to write an empty image");
    auto output = createOutput(file);
    const EncodedImage e = pixelsToWrite(image, file);
    if (output->supports("ioproxy")) writeThroughMemory(*output, e, file);
    else writeThroughTemporaryPath(e, file);
}

}  // namespace ray
