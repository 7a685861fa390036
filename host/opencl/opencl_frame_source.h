// Frames on OpenCL devices through the frame interface (render/frame_source.h), by the
// persistent engine (opencl_engine.h): the scene is packed and uploaded once, each camera or
// settings change only renders.
#pragma once

#include <memory>
#include <vector>

#include "opencl/opencl_device.h"
#include "opencl/opencl_engine.h"
#include "render/frame_source.h"

namespace ray {

class OpenClFrameSource : public FrameSource {
public:
    // Throws DeviceError for an empty selection.
    explicit OpenClFrameSource(std::vector<OpenClDevice> devices);
    ~OpenClFrameSource() override;
    uint64_t renderFrame(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                         const RenderSettings& settings, const std::function<void(const FrameTile&)>& onTile,
                         const std::atomic<bool>& cancel) override;
    std::string deviceName() const override;

private:
    std::vector<OpenClDevice> devices_;
    std::shared_ptr<const Scene> scene_;  // the scene engine_ was made for, kept alive for it
    std::unique_ptr<OpenClEngine> engine_;
};

}  // namespace ray
