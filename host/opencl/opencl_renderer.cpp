#include "opencl/opencl_renderer.h"

#include "opencl/opencl_engine.h"

namespace ray {

FrameResult renderOpenClFrame(const std::vector<OpenClDevice>& devices, const Scene& scene,
                              const RenderSettings& settings, const OpenClRenderOptions& options, RenderStats* stats) {
    OpenClEngine engine(scene, devices);
    FrameOptions frame;
    frame.tileSize = options.tileSize;
    frame.workGroupSize = options.workGroupSize;
    frame.progress = options.progress;
    frame.cancel = options.cancel;
    frame.eightBit = options.eightBit;
    FrameResult result = engine.renderFrame(scene.camera, settings, frame);
    if (stats) {
        RenderStats local;
        std::string names;
        for (const OpenClDevice& d : devices) names += (names.empty() ? "" : ", ") + d.description();
        local.device = names;
        local.primaryRays = result.stats.primaryRays;
        local.shadowRays = result.stats.shadowRays;
        local.secondaryRays = result.stats.secondaryRays;
        local.bvhBuildSeconds = result.stats.bvhBuildSeconds;
        local.kernelBuildSeconds = result.stats.kernelBuildSeconds;
        local.uploadSeconds = result.stats.uploadSeconds;
        local.renderSeconds = result.stats.renderSeconds;
        local.devices = result.stats.devices;
        local.warnings = result.stats.warnings;
        *stats = local;
    }
    return result;
}

Image renderOpenCl(const std::vector<OpenClDevice>& devices, const Scene& scene, const RenderSettings& settings,
                   const OpenClRenderOptions& options, RenderStats* stats) {
    OpenClRenderOptions floats = options;
    floats.eightBit = false;
    return std::move(renderOpenClFrame(devices, scene, settings, floats, stats).image);
}

Image renderOpenCl(const OpenClDevice& device, const Scene& scene, const RenderSettings& settings,
                   const OpenClRenderOptions& options, RenderStats* stats) {
    return renderOpenCl(std::vector<OpenClDevice>{device}, scene, settings, options, stats);
}

}  // namespace ray
