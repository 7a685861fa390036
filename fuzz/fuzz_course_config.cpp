// libFuzzer target: a course config's text (app/course_config.h) read over ray's default
// settings, strict and not. Anything but a clean InputError is a crash. Seeds: the course's
// configs and tests/data/fuzz/course_config (scripts/fuzz.sh); dictionary:
// fuzz/course_config.dict.
#include <cstdint>
#include <string>

#include "app/course_config.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    for (bool strict : {false, true}) {
        try {
            ray::readCourseConfig(text, "fuzzed.ini", ray::RenderSettings{}, strict);
        } catch (const ray::InputError&) {
            // A clean refusal: what bad input should get.
        }
    }
    return 0;
}
