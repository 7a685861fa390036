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

TEST_CASE("An image claiming more pixels than a texture's budget is refused before it is decoded", "[image]") {
    // 2,078 bytes: a run-length TGA header claiming 13,000 × 13,000 pixels (4.6 GB decoded),
    // then a few runs. Sniffed by content whatever its name, as a texture is.
    const fs::path claim = ray::test::testDataDir() / "fuzz" / "image_reader" / "tga_claims_13000x13000.tga";
    const fs::path dir = ray::test::outputDir() / "texture_budget";
    fs::create_directories(dir);
    for (const char* name : {"claim.tga", "claim.jpg", "claim"}) {
        fs::copy_file(claim, dir / name, fs::copy_options::overwrite_existing);
        CHECK_THROWS_WITH(ray::readImage(dir / name), Catch::Contains("13000 × 13000") &&
                                                          Catch::Contains("more than a texture's budget"));
    }
}

TEST_CASE("A 2 KB image that claims 13,000 × 13,000 pixels costs ray no more than a small scene", "[image][cli]") {
    const fs::path claim = ray::test::testDataDir() / "fuzz" / "image_reader" / "tga_claims_13000x13000.tga";
    const fs::path dir = ray::test::outputDir() / "texture_budget_render";
    fs::create_directories(dir);
    for (const char* name : {"claim.tga", "claim.jpg"}) {
        fs::copy_file(claim, dir / name, fs::copy_options::overwrite_existing);
        std::ofstream(dir / "scene.xml") << R"(<scenefile>
<cameradata><pos x="0" y="0" z="5"/><focus x="0" y="0" z="0"/><up x="0" y="1" z="0"/><heightangle v="45"/></cameradata>
<lightdata><id v="0"/><color r="1" g="1" b="1"/><position x="3" y="3" z="3"/></lightdata>
<object type="tree" name="root"><transblock><object type="primitive" name="sphere">
<diffuse r="1" g="1" b="1"/><texture file=")" << name << R"(" u="1" v="1"/><blend v="0.5"/>
</object></transblock></object></scenefile>
)";
        const ray::test::CommandResult run =
            ray::test::runRay({(dir / "scene.xml").string(), "32", "24", "--device", "ref", "-o", (dir / "out.png").string()});
        INFO(run.output);
        CHECK(run.exitCode == 0);
        CHECK_THAT(run.output, Catch::Contains("warning") && Catch::Contains("more than a texture's budget"));
        CHECK(run.peakMemoryKiB < 512 * 1024);
    }
}
