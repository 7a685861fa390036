// Rank 0's side of a distributed frame (mpi_render.h), apart from MPI so that it can be
// tested alone: the tiles it hands out on demand to the ranks (itself included), the image
// the finished tiles make, which rank holds which tile, and when each was handed out.
//
// Ranks that fail or hang do not stop the frame:
// - a rank whose devices all failed gives its tiles back (giveBack) to the others;
// - a rank that holds a tile past its deadline (lateRanks) is dropped (drop): it gets no
//   more tiles, and the tiles only it held go to the others first; a result it still
//   delivers is kept if it is the first;
// - at the end of the frame, when no tile is left to hand out, a rank that asks gets a
//   copy of a tile still pending on another rank, the one with the fewest ranks on it
//   (as the OpenCL engine does across the devices of one process). The first result wins.
//
// Deadlines come from the tile times seen (hand-out to delivery, across ranks): a tile is
// late after kSlowestTileFactor times the slowest tile so far, and never before
// kDeadlineFloorSeconds; a rank's tiles handed out before its first delivery wait behind
// its first kernel launch (PoCL compiles there), so they have kFirstTileSeconds. Timed from
// the rank's first delivery on, so that this start-up does not count as tile time.
// setDeadline (--rank-timeout) replaces all of this by one number.
//
// Thread-safe: rank 0's device threads and its message loop use it at once.
#pragma once

#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "image/image.h"
#include "render/tiles.h"

namespace ray {

class TileDispatcher {
public:
    // Seconds on a monotonic clock; a test passes its own.
    using Clock = std::function<double()>;
    static constexpr double kDeadlineFloorSeconds = 10;
    static constexpr double kSlowestTileFactor = 4;
    static constexpr double kFirstTileSeconds = 120;

    TileDispatcher(int width, int height, int tileSide, Clock clock = steadySeconds);

    // Up to `count` tiles for `rank`: those given back by a failed or dropped rank first,
    // then fresh ones in grid order, then (none left) copies of tiles pending on other
    // ranks. Empty when there is nothing for this rank (always, once it is dropped).
    std::vector<TileRect> handOut(int rank, int count);
    // A finished tile: pasted into the image unless another rank delivered it first (then
    // false, and it is dropped). Throws std::invalid_argument for a rectangle that is no
    // tile of the frame or a pixel count that does not match it (a protocol error).
    bool deliver(int rank, const TileRect& rect, const float* rgb, size_t floatCount);
    // `rank` stopped rendering: the tiles it still held go back to the queue. Returns how many.
    int giveBack(int rank);

    // The deadline in force for `rank`'s tiles, in seconds.
    double deadline(int rank) const;
    // Replaces the deadline of every tile (--rank-timeout); seconds > 0.
    void setDeadline(double seconds);
    // A late tile: who holds it, which, and for how long.
    struct Late {
        int rank;
        TileRect tile;
        double heldSeconds, deadlineSeconds;
    };
    // The ranks (not yet dropped) holding a tile past its deadline, one entry each.
    std::vector<Late> lateRanks() const;
    // No more tiles for `rank`; the tiles no other rank holds go to the others first.
    // Returns how many.
    int drop(int rank);
    bool dropped(int rank) const;

    bool complete() const;
    // Whether handOut(rank, 1) would give a tile now.
    bool anyToHandOut(int rank) const;
    double fractionDone() const;
    int tileCount() const { return grid_.count(); }
    int tileSide() const { return grid_.side(); }
    // The finished image (call when complete(); unrendered tiles are black).
    Image takeImage();

    static double steadySeconds();

private:
    enum class State { Queued, HandedOut, Done };
    struct Claim {
        int rank;
        double since;  // when the tile was handed to it
    };
    struct RankRecord {
        bool dropped = false;
        std::optional<double> firstDelivery;
    };
    RankRecord& record(int rank);
    const RankRecord* findRecord(int rank) const;
    std::optional<int> nextFor(int rank) const;  // under mutex_
    bool holds(int tile, int rank) const;
    double deadlineLocked(int rank) const;
    double heldSeconds(const Claim& claim, double now) const;
    void requeue(int tile);

    mutable std::mutex mutex_;
    Clock clock_;
    TileGrid grid_;
    Image image_;
    std::vector<State> state_;
    std::vector<std::vector<Claim>> claims_;  // the ranks holding each handed-out tile
    std::deque<int> givenBack_;               // tiles of failed/dropped ranks, before fresh ones
    std::vector<RankRecord> ranks_;           // by rank, grown as ranks appear
    int nextFresh_ = 0, done_ = 0;
    double slowestTile_ = 0;                  // seconds
    std::optional<double> fixedDeadline_;
};

}  // namespace ray
