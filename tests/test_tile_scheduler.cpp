// The tile grid (render/tiles.h) and the tile scheduler (render/tile_scheduler.h) that the
// OpenCL engine's devices and a distributed render's ranks share, alone.
#include <catch2/catch.hpp>

#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "image/image.h"
#include "render/tile_scheduler.h"
#include "render/tiles.h"

namespace {

// A tile's pixels, each the value v.
std::vector<float> filled(const ray::TileRect& rect, float v) { return std::vector<float>(rect.pixels() * 3, v); }

using Scheduler = ray::TileScheduler;

// A frame's scheduler and the image its kept tiles make, each tile painted with the
// number of the worker that delivered it.
struct Frame {
    Scheduler scheduler;
    ray::Image image;
    Frame(int width, int height, int side, Scheduler::Clock clock = Scheduler::steadySeconds)
        : scheduler(ray::TileGrid(width, height, side), std::move(clock)), image(width, height) {}
    // The tiles' rectangles.
    std::vector<ray::TileRect> handOut(int worker, int count) {
        std::vector<ray::TileRect> rects;
        for (int index : scheduler.handOut(worker, count)) rects.push_back(scheduler.tile(index));
        return rects;
    }
    bool deliver(int worker, const ray::TileRect& rect) {
        const std::optional<int> index = scheduler.indexOf(rect);
        REQUIRE(index);
        const std::vector<float> rgb = filled(rect, float(worker));
        return scheduler.deliver(worker, *index, [&] { ray::pasteTile(image, rect, rgb.data()); });
    }
    // The worker whose result the image kept at pixel (x, 0).
    float keptFrom(int x) const { return image.rgb[size_t(x) * 3]; }
};

}  // namespace

TEST_CASE("the tile grid covers the image once, cut at its edges", "[scheduler]") {
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

TEST_CASE("the scheduler hands each tile out once, and the first result wins", "[scheduler]") {
    Frame frame(40, 24, 16);  // 3 x 2 tiles
    Scheduler& s = frame.scheduler;
    REQUIRE(s.tileCount() == 6);
    std::vector<ray::TileRect> a = frame.handOut(1, 4), b = frame.handOut(2, 2);
    REQUIRE(a.size() == 4);
    REQUIRE(b.size() == 2);
    std::set<std::pair<int, int>> handed;
    for (const auto& t : a) handed.insert({t.x, t.y});
    for (const auto& t : b) handed.insert({t.x, t.y});
    CHECK(handed.size() == 6);  // each tile once
    for (const auto& t : a) REQUIRE(frame.deliver(1, t));
    CHECK_FALSE(s.complete());
    CHECK(s.tilesDone() == 4);
    for (const auto& t : b) REQUIRE(frame.deliver(2, t));
    // A duplicate is dropped: the first result stays.
    CHECK_FALSE(frame.deliver(3, a[0]));
    REQUIRE(s.complete());
    CHECK(s.fractionDone() == 1.0);
    CHECK(frame.image.rgb[0] == 1.0f);                          // tile 0, worker 1
    CHECK(frame.image.rgb[(size_t(23) * 40 + 39) * 3] == 2.0f);  // last tile, worker 2
}

TEST_CASE("a failed worker's tiles go to the others before fresh ones", "[scheduler]") {
    Frame frame(64, 16, 16);  // 4 tiles
    std::vector<ray::TileRect> lost = frame.handOut(1, 2);
    std::vector<ray::TileRect> kept = frame.handOut(2, 1);
    REQUIRE(frame.deliver(1, lost[0]));
    CHECK(frame.scheduler.giveBack(1) == 1);  // the one it had not delivered
    CHECK(frame.scheduler.giveBack(1) == 0);
    std::vector<ray::TileRect> next = frame.handOut(3, 1);
    REQUIRE(next.size() == 1);
    CHECK(next[0].x == lost[1].x);  // given back, so first
    std::set<int> rest;
    for (const auto& t : frame.handOut(0, 1)) rest.insert(t.x);
    CHECK(rest == std::set<int>{48});
    for (const auto& t : {next[0], kept[0], ray::TileRect{48, 0, 16, 16}}) REQUIRE(frame.deliver(0, t));
    CHECK(frame.scheduler.complete());
}

TEST_CASE("the scheduler knows its tiles by rectangle", "[scheduler]") {
    Scheduler s(ray::TileGrid(32, 32, 16));
    CHECK(s.indexOf({16, 16, 16, 16}) == 3);
    CHECK_FALSE(s.indexOf({8, 8, 16, 16}));
    CHECK_FALSE(s.indexOf({0, 0, 16, 8}));
    CHECK_FALSE(s.indexOf({32, 0, 16, 16}));
    Scheduler admitted;
    CHECK(admitted.admit({32, 0, 16, 16}) == 0);
    CHECK(admitted.indexOf({32, 0, 16, 16}) == 0);
    CHECK_FALSE(admitted.indexOf({0, 0, 16, 16}));
}

TEST_CASE("at the end of the frame, a worker gets copies of tiles pending on others", "[scheduler]") {
    Frame frame(48, 16, 16);  // 3 tiles
    Scheduler& s = frame.scheduler;
    std::vector<ray::TileRect> a = frame.handOut(1, 2), b = frame.handOut(2, 1);
    REQUIRE(a.size() == 2);
    REQUIRE(b.size() == 1);
    // Worker 2 finished its tile: it gets no copy while copies are not wanted (an engine's
    // device that still has launches in flight), then one of worker 1's, then the other,
    // then none.
    REQUIRE(frame.deliver(2, b[0]));
    CHECK(s.handOut(2, 4, Scheduler::Copies::None).empty());
    std::vector<ray::TileRect> copies = frame.handOut(2, 4);
    REQUIRE(copies.size() == 2);
    CHECK(std::set<int>{copies[0].x, copies[1].x} == std::set<int>{a[0].x, a[1].x});
    CHECK_FALSE(s.anyToHandOut(1));  // worker 1 holds every pending tile already
    CHECK(frame.handOut(1, 1).empty());
    // The first result wins; the copy is dropped.
    REQUIRE(frame.deliver(2, a[0]));
    CHECK_FALSE(frame.deliver(1, a[0]));
    REQUIRE(frame.deliver(1, a[1]));
    REQUIRE(s.complete());
    CHECK(frame.keptFrom(a[0].x) == 2.0f);
    CHECK(frame.keptFrom(a[1].x) == 1.0f);
}

TEST_CASE("a copy goes to the tile with the fewest workers on it", "[scheduler]") {
    Scheduler s(ray::TileGrid(32, 16, 16));  // 2 tiles
    REQUIRE(s.handOut(1, 1) == std::vector<int>{0});
    REQUIRE(s.handOut(2, 1) == std::vector<int>{1});
    CHECK(s.handOut(3, 1) == std::vector<int>{0});  // both held once: the longest held (tie: the first)
    CHECK(s.handOut(4, 1) == std::vector<int>{1});  // tile 1 has one worker, tile 0 two
}

TEST_CASE("admitted tiles: handed out as they come, copies and completion once admission closes",
          "[scheduler]") {
    Scheduler s;
    CHECK(s.handOut(1, 1).empty());
    CHECK_FALSE(s.complete());
    const int first = s.admit({0, 0, 8, 8});
    REQUIRE(s.handOut(1, 2) == std::vector<int>{first});
    CHECK(s.handOut(2, 1).empty());  // more may come: no copy yet
    REQUIRE(s.deliver(1, first));
    CHECK_FALSE(s.complete());       // more may come
    const int second = s.admit({8, 0, 8, 8});
    REQUIRE(s.handOut(1, 1) == std::vector<int>{second});
    s.closeAdmission();
    CHECK(s.handOut(2, 1) == std::vector<int>{second});  // now a copy
    REQUIRE(s.deliver(2, second));
    CHECK_FALSE(s.deliver(1, second));
    CHECK(s.complete());
    CHECK(s.tile(second).x == 8);
}

TEST_CASE("a failed worker's tile held by another too is not queued again", "[scheduler]") {
    Scheduler s(ray::TileGrid(16, 16, 16));  // 1 tile
    REQUIRE(s.handOut(1, 1).size() == 1);
    REQUIRE(s.handOut(2, 1).size() == 1);  // a copy
    CHECK(s.giveBack(1) == 1);
    CHECK_FALSE(s.anyToHandOut(2));  // worker 2 still renders it
    CHECK(s.handOut(3, 1) == std::vector<int>{0});  // a copy, not a queued tile
    CHECK(s.giveBack(2) == 1);
    CHECK(s.giveBack(3) == 1);
    CHECK(s.handOut(4, 1, Scheduler::Copies::None) == std::vector<int>{0});  // back in the queue
}

namespace {

// A clock the test moves by hand.
struct ManualClock {
    double now = 1000;
    Scheduler::Clock function() {
        return [this] { return now; };
    }
};

}  // namespace

TEST_CASE("a worker past its tile's deadline is reported, and once dropped its tiles go to the others", "[scheduler]") {
    ManualClock clock;
    Frame frame(64, 16, 16, clock.function());  // 4 tiles
    Scheduler& s = frame.scheduler;
    // Before a worker's first delivery its tiles wait behind its start-up.
    std::vector<ray::TileRect> one = frame.handOut(1, 1), two = frame.handOut(2, 1);
    clock.now += Scheduler::kFirstTileSeconds - 1;
    CHECK(s.lateWorkers().empty());
    CHECK(s.deadline(1) == Scheduler::kFirstTileSeconds);
    // A rank's silence is held to the usual deadline, even in its start-up.
    CHECK(s.usualDeadline() == Scheduler::kDeadlineFloorSeconds);
    REQUIRE(frame.deliver(1, one[0]));
    REQUIRE(frame.deliver(2, two[0]));
    // Both started: the floor, as no tile time is known yet.
    CHECK(s.deadline(1) == Scheduler::kDeadlineFloorSeconds);
    // A tile of 3 s sets the deadline to 4 x 3 s.
    one = frame.handOut(1, 1);
    clock.now += 3;
    REQUIRE(frame.deliver(1, one[0]));
    CHECK(s.deadline(2) == Approx(Scheduler::kSlowestTileFactor * 3));
    CHECK(s.usualDeadline() == Approx(Scheduler::kSlowestTileFactor * 3));
    // Worker 2 takes the last tile and stops answering.
    two = frame.handOut(2, 1);
    REQUIRE(two.size() == 1);
    clock.now += Scheduler::kSlowestTileFactor * 3 - 0.5;
    CHECK(s.lateWorkers().empty());
    clock.now += 1;
    std::vector<Scheduler::Late> late = s.lateWorkers();
    REQUIRE(late.size() == 1);
    CHECK(late[0].worker == 2);
    CHECK(late[0].tile.x == two[0].x);
    CHECK(late[0].heldSeconds > late[0].deadlineSeconds);
    CHECK(s.drop(2) == 1);
    CHECK(s.dropped(2));
    CHECK(s.lateWorkers().empty());  // a dropped worker is not reported again
    CHECK(s.handOut(2, 1).empty());
    // Its tile goes to another worker, whose result is kept; worker 2's late one is dropped.
    std::vector<ray::TileRect> again = frame.handOut(1, 1);
    REQUIRE(again.size() == 1);
    CHECK(again[0].x == two[0].x);
    REQUIRE(frame.deliver(1, again[0]));
    CHECK_FALSE(frame.deliver(2, two[0]));
    CHECK(s.complete());
}

TEST_CASE("a late worker's result, if first, is kept", "[scheduler]") {
    ManualClock clock;
    Frame frame(16, 16, 16, clock.function());  // 1 tile
    Scheduler& s = frame.scheduler;
    s.setDeadline(5);
    std::vector<ray::TileRect> tile = frame.handOut(1, 1);
    clock.now += 6;
    REQUIRE(s.lateWorkers().size() == 1);
    CHECK(s.drop(1) == 1);
    REQUIRE(frame.handOut(2, 1).size() == 1);
    REQUIRE(frame.deliver(1, tile[0]));
    CHECK(s.complete());
    CHECK_FALSE(frame.deliver(2, tile[0]));
    CHECK(frame.keptFrom(0) == 1.0f);
}

TEST_CASE("a dropped worker's late tile does not stretch the deadlines", "[scheduler]") {
    ManualClock clock;
    Frame frame(64, 16, 16, clock.function());  // 4 tiles
    Scheduler& s = frame.scheduler;
    std::vector<ray::TileRect> first = frame.handOut(1, 1);
    REQUIRE(frame.deliver(1, first[0]));
    std::vector<ray::TileRect> hung = frame.handOut(1, 1);
    clock.now += 100;  // it stopped
    REQUIRE(s.lateWorkers().size() == 1);
    s.drop(1);
    REQUIRE(frame.deliver(1, hung[0]));  // resumed
    CHECK(s.deadline(2) == Scheduler::kFirstTileSeconds);
    std::vector<ray::TileRect> next = frame.handOut(2, 1);
    REQUIRE(frame.deliver(2, next[0]));
    CHECK(s.deadline(2) == Scheduler::kDeadlineFloorSeconds);
}

TEST_CASE("the --rank-timeout option replaces the deadline, first tiles included", "[scheduler]") {
    ManualClock clock;
    Scheduler s(ray::TileGrid(32, 16, 16), clock.function());
    s.setDeadline(2.5);
    CHECK(s.deadline(1) == 2.5);
    CHECK(s.usualDeadline() == 2.5);
    s.handOut(1, 1);
    clock.now += 2;
    CHECK(s.lateWorkers().empty());
    clock.now += 1;
    CHECK(s.lateWorkers().size() == 1);
}

TEST_CASE("a tile whose only other holder was dropped goes back to the queue when its worker fails",
          "[scheduler]") {
    Scheduler s(ray::TileGrid(32, 16, 16));  // 2 tiles
    REQUIRE(s.handOut(1, 1) == std::vector<int>{0});
    CHECK(s.drop(1) == 1);                       // hung: tile 0 queued again
    REQUIRE(s.handOut(2, 1) == std::vector<int>{0});
    CHECK(s.giveBack(2) == 1);                   // failed: only the dropped worker holds it
    CHECK(s.handOut(3, 1, Scheduler::Copies::None) == std::vector<int>{0});
}
