// What the viewer asks of a renderer: one frame of a scene, reported band by band as it
// is finished, stopped early when `cancel` is set.
//
// A deliberately small seam: the reference renderer (ReferenceFrameSource, rows as bands)
// and the OpenCL engine that packs the scene once and renders tiles on the selected devices
// (OpenClFrameSource, viewer/opencl_frame_source.h) both implement it.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "render/render_settings.h"
#include "scene/scene.h"

namespace ray {

// A finished rectangle of the frame, 8-bit RGB as a png would hold it (SPEC §4).
struct FrameTile {
    int x = 0, y = 0, width = 0, height = 0;
    std::vector<uint8_t> rgb;
};

class FrameSource {
public:
    virtual ~FrameSource() = default;
    // Renders `scene` as `camera` sees it; onTile may be called from several threads.
    // Returns the rays traced (0 when cancelled early, the count is then partial). The
    // scene is shared so that a source may keep what it prepared for it between frames.
    virtual uint64_t renderFrame(const std::shared_ptr<const Scene>& scene, const Camera& camera, const RenderSettings& settings,
                                 const std::function<void(const FrameTile&)>& onTile,
                                 const std::atomic<bool>& cancel) = 0;
    virtual std::string deviceName() const = 0;
};

class ReferenceFrameSource : public FrameSource {
public:
    uint64_t renderFrame(const std::shared_ptr<const Scene>& scene, const Camera& camera, const RenderSettings& settings,
                         const std::function<void(const FrameTile&)>& onTile, const std::atomic<bool>& cancel) override;
    std::string deviceName() const override { return "reference (host, double precision)"; }
};

}  // namespace ray
