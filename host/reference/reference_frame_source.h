// Frames of the reference renderer (reference_renderer.h) through the frame interface
// (render/frame_source.h), each row a tile as it is finished.
#pragma once

#include <memory>
#include <string>

#include "render/frame_source.h"

namespace ray {

class ReferenceFrameSource : public FrameSource {
public:
    uint64_t renderFrame(const std::shared_ptr<const Scene>& scene, const Camera& camera, const RenderSettings& settings,
                         const std::function<void(const FrameTile&)>& onTile, const std::atomic<bool>& cancel) override;
    std::string deviceName() const override { return "reference (host, double precision)"; }
};

}  // namespace ray
