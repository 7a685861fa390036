#include "viewer/preview_resolution.h"

#include <algorithm>
#include <cmath>

namespace ray {

namespace {

// Each measurement counts for this much of the estimate: it follows a change of scene or
// load within a few previews, and one slow preview does not halve the next one's size.
constexpr double kWeightOfLatest = 0.5;

int dividedSide(int side, int divisor) { return std::max(1, (side + divisor - 1) / divisor); }

}  // namespace

PreviewSize dividedView(int width, int height, int divisor) {
    return {dividedSide(width, divisor), dividedSide(height, divisor), divisor};
}

PreviewSize PreviewResolution::size(int width, int height) const {
    const double budget = std::chrono::duration<double>(kPreviewBudget).count();
    const double fullSeconds = secondsPerPixel_ * double(width) * double(height);
    // Pixels go as the square of the divisor.
    const int divisor = std::clamp(int(std::ceil(std::sqrt(fullSeconds / budget))), 1, kMaxPreviewDivisor);
    return dividedView(width, height, divisor);
}

void PreviewResolution::rendered(double pixels, double seconds) {
    if (pixels <= 0 || !(seconds >= 0)) return;
    const double measured = seconds / pixels;
    secondsPerPixel_ = secondsPerPixel_ == 0 ? measured
                                             : (1 - kWeightOfLatest) * secondsPerPixel_ + kWeightOfLatest * measured;
}

void PreviewResolution::abandoned(double pixelsDone, double seconds) {
    if (!(seconds > 0)) return;
    secondsPerPixel_ = std::max(secondsPerPixel_, seconds / std::max(pixelsDone, 1.0));
}

}  // namespace ray
