// One frame of a scene, as a renderer makes it for a caller that shows it as it comes: the
// frame of a scene seen by a camera with settings, reported tile by tile as each is
// finished, stopped early when `cancel` is set.
//
// A deliberately small seam: the reference renderer (reference/reference_frame_source.h,
// rows as tiles) and the OpenCL engine, which packs the scene once and renders tiles on the
// selected devices (opencl/opencl_frame_source.h), both implement it; devices/renderer.h
// makeFrameSource picks one from a device string. The viewer renders through it.
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

}  // namespace ray
