// PNG and JPEG through libpng and libjpeg (image/png_codec.h, image/jpeg_codec.h) against
// OpenImageIO (image/oiio_module.h), which decoded every texture before: the values must
// not change, or every textured render would.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "image/image.h"
#include "image/jpeg_codec.h"
#include "image/oiio_module.h"
#include "image/png_codec.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace {

bool isPngOrJpegName(const fs::path& file) {
    std::string ext = file.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".png" || ext == ".jpg" || ext == ".jpeg";
}

// Every PNG and JPEG of the course corpus: its textures and its reference renders.
std::vector<fs::path> courseImages(const fs::path& shared) {
    std::vector<fs::path> images;
    for (const auto& entry : fs::recursive_directory_iterator(shared / "cs123"))
        if (entry.is_regular_file() && isPngOrJpegName(entry.path())) images.push_back(entry.path());
    return images;
}

}  // namespace

TEST_CASE("libpng and libjpeg decode every course image exactly as OpenImageIO does", "[image]") {
    const auto shared = ray::test::sharedDir();
    if (!shared) {
        ray::test::skip("../shared/cs123 is absent");
        return;
    }
    const auto images = courseImages(*shared);
    int png = 0, jpeg = 0;
    for (const fs::path& file : images) {
        INFO(file);
        const bool isPng = ray::hasPngSignature(file), isJpeg = ray::hasJpegSignature(file);
        REQUIRE((isPng || isJpeg));
        png += isPng, jpeg += isJpeg;
        const ray::Image direct = isPng ? ray::readPng(file) : ray::readJpeg(file);
        const ray::Image viaOiio = ray::readImageWithOiio(file);
        REQUIRE(direct.width == viaOiio.width);
        REQUIRE(direct.height == viaOiio.height);
        // A count, not the vectors: Catch would print millions of floats on a mismatch.
        size_t differing = 0;
        for (size_t i = 0; i < direct.rgb.size(); ++i) differing += direct.rgb[i] != viaOiio.rgb[i];
        CHECK(differing == 0);
    }
    CHECK(png > 0);
    CHECK(jpeg > 0);
}

TEST_CASE("A written PNG reads back as the 8-bit values SPEC section 4 prescribes", "[image]") {
    ray::Image image(7, 3);
    for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = float(i) / 40.0f - 0.1f;  // below 0 to above 1
    image.rgb[4] = std::numeric_limits<float>::quiet_NaN();
    const fs::path file = ray::test::outputDir() / "codec_roundtrip.png";
    ray::writeImage(image, file);
    const ray::Image ours = ray::readImage(file), theirs = ray::readImageWithOiio(file);
    REQUIRE(ours.width == 7);
    REQUIRE(ours.height == 3);
    CHECK(ours.rgb == theirs.rgb);
    for (size_t i = 0; i < image.rgb.size(); ++i)
        CHECK(ours.rgb[i] == float(ray::quantize8(image.rgb[i])) * (1.0f / 255.0f));
}

TEST_CASE("Broken PNG and JPEG files are refused with the file's name", "[image]") {
    const fs::path dir = ray::test::outputDir();
    const fs::path png = dir / "truncated.png", jpeg = dir / "truncated.jpg";
    ray::Image image(64, 64);
    ray::writeImage(image, png);
    fs::resize_file(png, fs::file_size(png) / 2);
    {
        std::ofstream out(jpeg, std::ios::binary);
        out << "\xFF\xD8\xFF\xE0garbage";
    }
    for (const fs::path& file : {png, jpeg}) {
        try {
            ray::readImage(file);
            FAIL("no error for " << file);
        } catch (const ray::ImageError& e) {
            CHECK_THAT(e.what(), Catch::Contains(file.string()));
        }
    }
}
