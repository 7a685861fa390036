// Frames of the reference renderer (reference_renderer.h) through the frame interface
// (render/frame_source.h), each row a tile as it is finished. It renders whole frames only
// (no FrameRequest::tiles) and builds its BVH for every frame.
#pragma once

#include <memory>
#include <string>

#include "render/frame_source.h"

namespace ray {

class ReferenceFrameSource : public FrameSource {
public:
    // bruteForce: test every primitive for every ray (--no-bvh).
    explicit ReferenceFrameSource(bool bruteForce = false) : bruteForce_(bruteForce) {}
    RenderedFrame render(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                         const RenderSettings& settings, const FrameRequest& request) override;
    std::string deviceName() const override { return "reference (host, double precision)"; }

private:
    bool bruteForce_;
};

}  // namespace ray
