// Frames on OpenCL devices through the frame interface (render/frame_source.h), by the
// persistent engine (opencl_engine.h): the scene is packed and uploaded once, each camera or
// settings change only renders. Every device of the selection cooperates on each frame.
#pragma once

#include <memory>
#include <vector>

#include "opencl/opencl_device.h"
#include "opencl/opencl_engine.h"
#include "render/frame_source.h"

namespace ray {

class OpenClFrameSource : public FrameSource {
public:
    // Throws DeviceError for an empty selection. Nothing starts before the first frame.
    explicit OpenClFrameSource(std::vector<OpenClDevice> devices);
    ~OpenClFrameSource() override;
    // Throws DeviceError (build failure, device limits, out of memory, every device failed;
    // devices dropped on the way are named in the stats' warnings) and InputError.
    RenderedFrame render(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                         const RenderSettings& settings, const FrameRequest& request) override;
    std::string deviceName() const override;

private:
    std::vector<OpenClDevice> devices_;
    std::shared_ptr<const Scene> scene_;  // the scene engine_ was made for, kept alive for it
    std::unique_ptr<OpenClEngine> engine_;
};

}  // namespace ray
