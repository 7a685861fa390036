// What the scene fuzzers do with a fuzzed text, whatever its format: load it, pack it for the
// kernel and render a few pixels with the reference renderer. A clean refusal (InputError) is
// what bad input should get; anything else is a finding.
#pragma once

#include <filesystem>
#include <string>

#include "opencl/scene_packing.h"
#include "reference/reference_renderer.h"
#include "scene/scene_loader.h"

namespace ray::fuzz {

inline void loadPackAndRender(const std::string& text, const std::filesystem::path& file, LoadOptions options) {
    // Far below the real limit, so that a legitimately big scene does not trip libFuzzer's
    // memory limit; the real limit has its own tests.
    options.maxPrimitives = 20000;
    options.warn = [](const std::string&) {};
    try {
        Scene scene = loadSceneFromText(text, file, options);
        PackedScene packed = packScene(scene);
        RenderSettings settings;
        settings.width = 4;
        settings.height = 3;
        settings.maxDepth = 2;
        settings.antialias = AntialiasMode::Off;
        ReferenceRenderOptions render;
        render.threads = 1;
        renderReference(scene, settings, render);
    } catch (const InputError&) {
    }
}

}  // namespace ray::fuzz
