#include "opencl/opencl_renderer.h"

#include "opencl/opencl_frame_source.h"

namespace ray {

Image renderOpenCl(const std::vector<OpenClDevice>& devices, const Scene& scene, const RenderSettings& settings,
                   const OpenClRenderOptions& options, RenderStats* stats) {
    FrameRequest floats = options;
    floats.eightBit = false;
    floats.tiles = nullptr;
    RenderedFrame frame = OpenClFrameSource(devices).render(borrowedScene(scene), scene.camera, settings, floats);
    if (stats) *stats = std::move(frame.stats);
    return std::move(frame.image);
}

Image renderOpenCl(const OpenClDevice& device, const Scene& scene, const RenderSettings& settings,
                   const OpenClRenderOptions& options, RenderStats* stats) {
    return renderOpenCl(std::vector<OpenClDevice>{device}, scene, settings, options, stats);
}

}  // namespace ray
