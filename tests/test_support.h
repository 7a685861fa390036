// Helpers shared by the tests: where the data is, and comparing images.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli.h"
#include "image.h"

namespace ray::test {

// ../shared beside the checkout (or $RAY_SHARED_DIR); nullopt when absent.
inline std::optional<std::filesystem::path> sharedDir() {
    std::filesystem::path dir = RAY_TEST_SHARED_DIR;
    if (const char* env = std::getenv("RAY_SHARED_DIR")) dir = env;
    if (std::filesystem::is_directory(dir / "cs123")) return dir;
    return std::nullopt;
}

// Prints the marker CTest turns into a skip (tests/CMakeLists.txt).
inline void skip(const std::string& why) { std::cout << "SKIPPED: " << why << std::endl; }

inline std::filesystem::path scenesDir() { return RAY_TEST_SCENES_DIR; }
inline std::filesystem::path testDataDir() { return RAY_TEST_DATA_DIR; }
inline std::filesystem::path outputDir() {
    std::filesystem::path dir = RAY_TEST_OUTPUT_DIR;
    std::filesystem::create_directories(dir);
    return dir;
}

struct ImageDifference {
    double fractionWithin = 0;  // pixels whose every channel differs by at most the tolerance
    double meanAbsError = 0;    // over all channels, in 8-bit levels
    int maxError = 0;           // in 8-bit levels
};

// Compares two images as the 8-bit values SPEC §4 writes (floor(255·clamp(c))).
inline ImageDifference compare8bit(const Image& a, const Image& b, int toleranceLevels) {
    ImageDifference d;
    if (a.width != b.width || a.height != b.height) return d;
    size_t within = 0, pixels = size_t(a.width) * size_t(a.height);
    double sum = 0;
    for (size_t p = 0; p < pixels; ++p) {
        int worst = 0;
        for (int c = 0; c < 3; ++c) {
            int e = std::abs(quantize8(a.rgb[p * 3 + c]) - quantize8(b.rgb[p * 3 + c]));
            worst = std::max(worst, e);
            sum += e;
        }
        d.maxError = std::max(d.maxError, worst);
        if (worst <= toleranceLevels) ++within;
    }
    d.fractionWithin = pixels ? double(within) / double(pixels) : 0;
    d.meanAbsError = pixels ? sum / double(pixels * 3) : 0;
    return d;
}

// |a − b| ×4 per channel in 8-bit levels, for looking at where two images differ.
inline Image differenceImage(const Image& a, const Image& b) {
    Image d(a.width, a.height);
    for (size_t i = 0; i < d.rgb.size() && i < b.rgb.size(); ++i)
        d.rgb[i] = std::min(1.0f, 4.0f * float(std::abs(quantize8(a.rgb[i]) - quantize8(b.rgb[i]))) / 255.0f);
    return d;
}

// A row of ../shared/cs123/reference/INDEX.tsv: a course render and how to reproduce it.
struct ReferenceCase {
    std::string image;    // the course's render, in cs123/reference/
    std::string scene;    // relative to cs123/
    std::string options;  // ray's command-line options that match the course's settings
};

inline std::vector<ReferenceCase> readReferenceIndex(const std::filesystem::path& indexFile) {
    std::vector<ReferenceCase> cases;
    std::ifstream in(indexFile);
    std::string line;
    std::getline(in, line);  // the header
    while (std::getline(in, line)) {
        std::vector<std::string> fields;
        std::stringstream columns(line);
        for (std::string field; std::getline(columns, field, '\t');) fields.push_back(field);
        if (fields.size() >= 4) cases.push_back({fields[0], fields[1], fields[3]});
    }
    return cases;
}

// Render settings from command-line option words, read by ray's own parser.
inline RenderSettings settingsFromOptions(const std::string& options, int width, int height, int depth = 4) {
    std::vector<std::string> args{"scene.xml", std::to_string(width), std::to_string(height), std::to_string(depth)};
    std::stringstream words(options);
    for (std::string word; words >> word;) args.push_back(word);
    return parseCommandLine(args).settings;
}

}  // namespace ray::test
