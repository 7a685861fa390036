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
    std::vector<ray::TileRect> a = dispatcher.handOut(1, 4), b = dispatcher.handOut(2, 2);
    REQUIRE(a.size() == 4);
    REQUIRE(b.size() == 2);
    std::set<int> handed;
    for (const auto& t : a) handed.insert(dispatcher.tileCount() * t.y + t.x);
    for (const auto& t : b) handed.insert(dispatcher.tileCount() * t.y + t.x);
    CHECK(handed.size() == 6);  // each tile once
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
    std::vector<ray::TileRect> next = dispatcher.handOut(3, 1);
    REQUIRE(next.size() == 1);
    CHECK(next[0].x == lost[1].x);  // given back, so first
    std::set<int> rest;
    for (const auto& t : dispatcher.handOut(0, 1)) rest.insert(t.x);
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

TEST_CASE("at the end of the frame, a rank gets copies of tiles pending on others", "[distributed]") {
    ray::TileDispatcher dispatcher(48, 16, 16);  // 3 tiles
    std::vector<ray::TileRect> a = dispatcher.handOut(1, 2), b = dispatcher.handOut(2, 1);
    REQUIRE(a.size() == 2);
    REQUIRE(b.size() == 1);
    // Rank 2 finished its tile: it gets a copy of one of rank 1's, then the other, then none.
    REQUIRE(dispatcher.deliver(2, b[0], filled(b[0], 2).data(), b[0].pixels() * 3));
    std::vector<ray::TileRect> copies = dispatcher.handOut(2, 4);
    REQUIRE(copies.size() == 2);
    CHECK(std::set<int>{copies[0].x, copies[1].x} == std::set<int>{a[0].x, a[1].x});
    CHECK_FALSE(dispatcher.anyToHandOut(1));  // rank 1 holds every pending tile already
    CHECK(dispatcher.handOut(1, 1).empty());
    // The first result wins; the copy is dropped.
    REQUIRE(dispatcher.deliver(2, a[0], filled(a[0], 2).data(), a[0].pixels() * 3));
    CHECK_FALSE(dispatcher.deliver(1, a[0], filled(a[0], 1).data(), a[0].pixels() * 3));
    REQUIRE(dispatcher.deliver(1, a[1], filled(a[1], 1).data(), a[1].pixels() * 3));
    REQUIRE(dispatcher.complete());
    ray::Image image = dispatcher.takeImage();
    CHECK(image.rgb[size_t(a[0].x) * 3] == 2.0f);
    CHECK(image.rgb[size_t(a[1].x) * 3] == 1.0f);
}

namespace {

// A clock the test moves by hand.
struct ManualClock {
    double now = 1000;
    ray::TileDispatcher::Clock function() {
        return [this] { return now; };
    }
};

}  // namespace

TEST_CASE("a rank past its tile's deadline is reported; dropped, its tiles go to the others", "[distributed]") {
    using D = ray::TileDispatcher;
    ManualClock clock;
    D dispatcher(64, 16, 16, clock.function());  // 4 tiles
    // Before a rank's first delivery its tiles wait behind its start-up.
    std::vector<ray::TileRect> one = dispatcher.handOut(1, 1), two = dispatcher.handOut(2, 1);
    clock.now += D::kFirstTileSeconds - 1;
    CHECK(dispatcher.lateRanks().empty());
    CHECK(dispatcher.deadline(1) == D::kFirstTileSeconds);
    REQUIRE(dispatcher.deliver(1, one[0], filled(one[0], 1).data(), one[0].pixels() * 3));
    REQUIRE(dispatcher.deliver(2, two[0], filled(two[0], 2).data(), two[0].pixels() * 3));
    // Both started: the floor, as no tile time is known yet.
    CHECK(dispatcher.deadline(1) == D::kDeadlineFloorSeconds);
    // A tile of 3 s sets the deadline to 4 x 3 s.
    one = dispatcher.handOut(1, 1);
    clock.now += 3;
    REQUIRE(dispatcher.deliver(1, one[0], filled(one[0], 1).data(), one[0].pixels() * 3));
    CHECK(dispatcher.deadline(2) == Approx(D::kSlowestTileFactor * 3));
    // Rank 2 takes the last tile and stops answering.
    two = dispatcher.handOut(2, 1);
    REQUIRE(two.size() == 1);
    clock.now += D::kSlowestTileFactor * 3 - 0.5;
    CHECK(dispatcher.lateRanks().empty());
    clock.now += 1;
    std::vector<D::Late> late = dispatcher.lateRanks();
    REQUIRE(late.size() == 1);
    CHECK(late[0].rank == 2);
    CHECK(late[0].tile.x == two[0].x);
    CHECK(late[0].heldSeconds > late[0].deadlineSeconds);
    CHECK(dispatcher.drop(2) == 1);
    CHECK(dispatcher.dropped(2));
    CHECK(dispatcher.lateRanks().empty());  // a dropped rank is not reported again
    CHECK(dispatcher.handOut(2, 1).empty());
    // Its tile goes to another rank, whose result is kept; rank 2's late one is dropped.
    std::vector<ray::TileRect> again = dispatcher.handOut(1, 1);
    REQUIRE(again.size() == 1);
    CHECK(again[0].x == two[0].x);
    REQUIRE(dispatcher.deliver(1, again[0], filled(again[0], 1).data(), again[0].pixels() * 3));
    CHECK_FALSE(dispatcher.deliver(2, two[0], filled(two[0], 2).data(), two[0].pixels() * 3));
    CHECK(dispatcher.complete());
}

TEST_CASE("a late rank's result, if first, is kept", "[distributed]") {
    ManualClock clock;
    ray::TileDispatcher dispatcher(16, 16, 16, clock.function());  // 1 tile
    dispatcher.setDeadline(5);
    std::vector<ray::TileRect> tile = dispatcher.handOut(1, 1);
    clock.now += 6;
    REQUIRE(dispatcher.lateRanks().size() == 1);
    CHECK(dispatcher.drop(1) == 1);
    REQUIRE(dispatcher.handOut(2, 1).size() == 1);
    REQUIRE(dispatcher.deliver(1, tile[0], filled(tile[0], 1).data(), tile[0].pixels() * 3));
    CHECK(dispatcher.complete());
    CHECK_FALSE(dispatcher.deliver(2, tile[0], filled(tile[0], 2).data(), tile[0].pixels() * 3));
    CHECK(dispatcher.takeImage().rgb[0] == 1.0f);
}

TEST_CASE("a dropped rank's late tile does not stretch the deadlines", "[distributed]") {
    using D = ray::TileDispatcher;
    ManualClock clock;
    D dispatcher(64, 16, 16, clock.function());  // 4 tiles
    std::vector<ray::TileRect> first = dispatcher.handOut(1, 1);
    REQUIRE(dispatcher.deliver(1, first[0], filled(first[0], 1).data(), first[0].pixels() * 3));
    std::vector<ray::TileRect> hung = dispatcher.handOut(1, 1);
    clock.now += 100;  // it stopped
    REQUIRE(dispatcher.lateRanks().size() == 1);
    dispatcher.drop(1);
    REQUIRE(dispatcher.deliver(1, hung[0], filled(hung[0], 1).data(), hung[0].pixels() * 3));  // resumed
    CHECK(dispatcher.deadline(2) == D::kFirstTileSeconds);
    std::vector<ray::TileRect> next = dispatcher.handOut(2, 1);
    REQUIRE(dispatcher.deliver(2, next[0], filled(next[0], 2).data(), next[0].pixels() * 3));
    CHECK(dispatcher.deadline(2) == D::kDeadlineFloorSeconds);
}

TEST_CASE("the --rank-timeout option replaces the deadline, first tiles included", "[distributed]") {
    ManualClock clock;
    ray::TileDispatcher dispatcher(32, 16, 16, clock.function());
    dispatcher.setDeadline(2.5);
    CHECK(dispatcher.deadline(1) == 2.5);
    dispatcher.handOut(1, 1);
    clock.now += 2;
    CHECK(dispatcher.lateRanks().empty());
    clock.now += 1;
    CHECK(dispatcher.lateRanks().size() == 1);
}
