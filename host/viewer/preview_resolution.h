// How large to render a preview, the frame shown while something moves (a drag of the
// camera or of an object): the view's own size when that is quick enough, else the view's
// size divided by a whole number, so that a preview takes about kPreviewBudget and a drag
// shows ten or more a second. The page scales a smaller preview up to the view. The cost
// of a pixel is learnt from the previews rendered so far, so it follows the scene, the
// settings, the device and the load of the machine.
#pragma once

#include <chrono>

namespace ray {

// What a preview may take to render. The page also decodes and draws it, and a drag's
// request waits for the preview in flight (frame_schedule.cpp): 40 ms leaves room for both
// within 100 ms.
constexpr std::chrono::milliseconds kPreviewBudget{40};
// Beyond 8 a preview is too coarse to show what moves (1280x720 / 8 = 160x90).
constexpr int kMaxPreviewDivisor = 8;

struct PreviewSize {
    int width = 0, height = 0;
    int divisor = 1;  // the view's size over the preview's
};

// A width x height view divided by `divisor`, each side rounded up.
PreviewSize dividedView(int width, int height, int divisor);

class PreviewResolution {
public:
    // The preview of a width x height view.
    PreviewSize size(int width, int height) const;
    // A preview of `pixels` was rendered in `seconds`.
    void rendered(double pixels, double seconds);
    // A preview was given up after `seconds`, with `pixelsDone` of its pixels rendered:
    // a pixel costs at least seconds / pixelsDone.
    void abandoned(double pixelsDone, double seconds);
    double secondsPerPixel() const { return secondsPerPixel_; }

private:
    double secondsPerPixel_ = 0;  // 0: no preview measured yet (the first is full size)
};

}  // namespace ray
