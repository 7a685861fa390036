// The preview's size while something moves (viewer/preview_resolution.h): full size when
// quick, a whole divisor of the view's size that fits the budget otherwise, following the
// measured cost.
#include <catch2/catch.hpp>

#include "viewer/preview_resolution.h"

using namespace ray;

namespace {
const double kBudget = std::chrono::duration<double>(kPreviewBudget).count();
}

TEST_CASE("preview resolution: the first preview is the view's own size", "[viewer]") {
    const PreviewSize size = PreviewResolution().size(1280, 720);
    CHECK(size.divisor == 1);
    CHECK(size.width == 1280);
    CHECK(size.height == 720);
}

TEST_CASE("preview resolution: a view that renders within the budget stays full size", "[viewer]") {
    PreviewResolution resolution;
    resolution.rendered(1280.0 * 720, kBudget * 0.9);
    CHECK(resolution.size(1280, 720).divisor == 1);
}

TEST_CASE("preview resolution: a slow view is divided so that its preview fits the budget", "[viewer]") {
    PreviewResolution resolution;
    // Twice the budget at full size: a half-size preview costs a quarter, within it.
    resolution.rendered(1280.0 * 720, kBudget * 2);
    const PreviewSize size = resolution.size(1280, 720);
    CHECK(size.divisor == 2);
    CHECK(size.width == 640);
    CHECK(size.height == 360);
    // A divisor that does not divide the side rounds the preview's side up.
    CHECK(resolution.size(1281, 721).width == 641);
}

TEST_CASE("preview resolution: the cost follows later previews and stops at 1/8", "[viewer]") {
    PreviewResolution resolution;
    resolution.rendered(1000, kBudget * 1000);  // absurdly slow: the coarsest preview
    CHECK(resolution.size(1280, 720).divisor == kMaxPreviewDivisor);
    for (int i = 0; i < 40; ++i) resolution.rendered(1280.0 * 720, kBudget / 2);  // then quick again
    CHECK(resolution.size(1280, 720).divisor == 1);
}

TEST_CASE("preview resolution: a preview given up teaches a lower bound of the cost", "[viewer]") {
    PreviewResolution resolution;
    resolution.rendered(1280.0 * 720, kBudget / 2);
    // Given up after 4 budgets with a quarter of its pixels done: a pixel costs 16 times
    // what the budget allows for full size, so the divisor is 4.
    resolution.abandoned(1280.0 * 720 / 4, kBudget * 4);
    CHECK(resolution.size(1280, 720).divisor == 4);
}
