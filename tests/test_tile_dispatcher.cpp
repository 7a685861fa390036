// The tile grid (render/tiles.h) and rank 0's tile dispatcher of a distributed render
// (distributed/tile_dispatcher.h), without MPI.
#include <catch2/catch.hpp>

#include <set>
#include <stdexcept>
#include <vector>

#include "distributed/tile_dispatcher.h"
#include "render/tiles.h"

namespace {

// A tile's pixels, each the value v.
std::vector<float> filled(const ray::TileRect& rect, float v) { return std::vector<float>(rect.pixels() * 3, v); }

}  // namespace

TEST_CASE("the tile grid covers the image once, cut at its edges", "[distributed]") {
    for (auto [w, h, side] : {std::tuple{100, 70, 16}, {5, 3, 64}, {64, 64, 64}, {1, 1, 8}}) {
        ray::TileGrid grid(w, h, side);
        std::vector<int> covered(size_t(w * h), 0);
        for (int i = 0; i < grid.count(); ++i) {
            ray::TileRect t = grid.tile(i);
            REQUIRE(grid.indexOf(t) == i);
            for (int y = t.y; y < t.y + t.height; ++y)
                for (int x = t.x; x < t.x + t.width; ++x) ++covered[size_t(y * w + x)];
        }
        for (int c : covered) REQUIRE(c == 1);
    }
    ray::TileGrid grid(100, 70, 16);
    CHECK(grid.indexOf({16, 0, 16, 16}) == 1);
    CHECK(grid.indexOf({8, 0, 16, 16}) == -1);   // not on the grid
    CHECK(grid.indexOf({96, 64, 16, 16}) == -1); // the corner tile is 4x6
    CHECK(grid.indexOf({96, 64, 4, 6}) == grid.count() - 1);
    CHECK(grid.indexOf({112, 0, 16, 16}) == -1); // outside
}

TEST_CASE("the dispatcher hands each tile out once and assembles the image", "[distributed]") {
    ray::TileDispatcher dispatcher(40, 24, 16);  // 3 x 2 tiles
    REQUIRE(dispatcher.tileCount() == 6);
    std::vector<ray::TileRect> a = dispatcher.handOut(1, 4), b = dispatcher.handOut(2, 4);
    REQUIRE(a.size() == 4);
    REQUIRE(b.size() == 2);  // fewer than asked: none left
    CHECK(dispatcher.handOut(0, 1).empty());
    CHECK_FALSE(dispatcher.anyToHandOut());
    for (const auto& t : a) REQUIRE(dispatcher.deliver(1, t, filled(t, 1).data(), t.pixels() * 3));
    CHECK_FALSE(dispatcher.complete());
    for (const auto& t : b) REQUIRE(dispatcher.deliver(2, t, filled(t, 2).data(), t.pixels() * 3));
    // A duplicate is dropped: the first result stays.
    CHECK_FALSE(dispatcher.deliver(2, a[0], filled(a[0], 9).data(), a[0].pixels() * 3));
    REQUIRE(dispatcher.complete());
    CHECK(dispatcher.fractionDone() == 1.0);
    ray::Image image = dispatcher.takeImage();
    CHECK(image.rgb[0] == 1.0f);                                     // tile 0, rank 1
    CHECK(image.rgb[(size_t(23) * 40 + 39) * 3] == 2.0f);             // last tile, rank 2
}

TEST_CASE("a failed rank's tiles go to the others before fresh ones", "[distributed]") {
    ray::TileDispatcher dispatcher(64, 16, 16);  // 4 tiles
    std::vector<ray::TileRect> lost = dispatcher.handOut(1, 2);
    std::vector<ray::TileRect> kept = dispatcher.handOut(2, 1);
    REQUIRE(dispatcher.deliver(1, lost[0], filled(lost[0], 1).data(), lost[0].pixels() * 3));
    CHECK(dispatcher.giveBack(1) == 1);  // the one it had not delivered
    CHECK(dispatcher.giveBack(1) == 0);
    std::vector<ray::TileRect> next = dispatcher.handOut(0, 1);
    REQUIRE(next.size() == 1);
    CHECK(next[0].x == lost[1].x);  // given back, so first
    std::set<int> rest;
    for (const auto& t : dispatcher.handOut(0, 8)) rest.insert(t.x);
    CHECK(rest == std::set<int>{48});
    for (const auto& t : {next[0], kept[0], ray::TileRect{48, 0, 16, 16}})
        REQUIRE(dispatcher.deliver(0, t, filled(t, 3).data(), t.pixels() * 3));
    CHECK(dispatcher.complete());
}

TEST_CASE("the dispatcher refuses a result that is no tile of the frame", "[distributed]") {
    ray::TileDispatcher dispatcher(32, 32, 16);
    std::vector<float> rgb(16 * 16 * 3, 0.5f);
    CHECK_THROWS_AS(dispatcher.deliver(1, {8, 8, 16, 16}, rgb.data(), rgb.size()), std::invalid_argument);
    CHECK_THROWS_AS(dispatcher.deliver(1, {0, 0, 16, 16}, rgb.data(), rgb.size() - 3), std::invalid_argument);
    CHECK_THROWS_AS(dispatcher.deliver(1, {32, 0, 16, 16}, rgb.data(), rgb.size()), std::invalid_argument);
    CHECK_FALSE(dispatcher.complete());
}
