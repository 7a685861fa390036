// The one tile scheduler: which worker renders which tile of a frame. The OpenCL engine's
// device threads are its workers within a process (opencl/device_worker.cpp); the ranks of
// a distributed render are its workers on rank 0 (distributed/mpi_coordinator.cpp). It knows
// nothing of either transport, so that it is tested alone (tests/test_tile_scheduler.cpp).
//
// A tile is queued, handed out (to one or more workers), or done. The tiles are the cells
// of a grid, or are admitted one by one as they arrive from an upstream scheduler (a rank's
// devices render the tiles rank 0 hands the rank); then the frame ends when admission is
// closed and every admitted tile is done.
//
// Workers that fail or hang do not stop the frame:
// - a worker that fails gives its tiles back (giveBack) to the others;
// - a worker taken for hung is dropped (drop): it gets no more tiles, and the tiles only it
//   held go to the others first; a result it still delivers is kept if it is the first;
// - at the end of the frame, when no tile is left to hand out, a worker that asks gets a
//   copy of a tile still pending on another worker, the one with the fewest workers on it,
//   the longest held of those. The first result wins (deliver), the copy is dropped.
//
// Deadlines (used for ranks; the engine times its devices itself, as their launches finish
// in order and their programs compile at the first launch): a tile is late after
// kSlowestTileFactor times the slowest tile so far (hand-out to delivery, across workers),
// and never before kDeadlineFloorSeconds; a worker's tiles handed out before its first
// delivery wait behind its start-up (PoCL compiles at the first launch), so they have
// kFirstTileSeconds. Timed from the worker's first delivery on, so that this start-up does
// not count as tile time. setDeadline (--rank-timeout) replaces all of this by one number.
//
// Thread-safe: the workers' threads and a message loop use it at once.
#pragma once

#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <vector>

#include "render/tiles.h"

namespace ray {

class TileScheduler {
public:
    // Seconds on a monotonic clock; a test passes its own.
    using Clock = std::function<double()>;
    static constexpr double kDeadlineFloorSeconds = 10;
    static constexpr double kSlowestTileFactor = 4;
    static constexpr double kFirstTileSeconds = 120;

    // Every tile of the grid, handed out in grid order.
    explicit TileScheduler(const TileGrid& grid, Clock clock = steadySeconds);
    // No tile yet: they are admitted (admit) as they arrive, until closeAdmission.
    explicit TileScheduler(Clock clock = steadySeconds);

    // Adds a tile to hand out after those admitted before; returns its index.
    int admit(const TileRect& rect);
    // No more tiles will be admitted: the frame is complete once those admitted are done,
    // and workers that ask may now get copies of pending tiles.
    void closeAdmission();

    // Whether a worker may get a copy of a tile pending on another (end of the frame).
    enum class Copies { Allowed, None };
    // Up to `count` tile indices for `worker`: those given back by a failed or dropped
    // worker first, then fresh ones in order, then (none left, admission closed, copies
    // allowed) copies of tiles pending on other workers. Empty when there is nothing for
    // this worker (always, once it is dropped).
    std::vector<int> handOut(int worker, int count, Copies copies = Copies::Allowed);
    // A finished tile, from `worker`: true when it is the tile's first result. `keep`, if
    // given, runs then, under the scheduler's lock, before the tile counts as done: what it
    // writes (the tile's pixels) is in place once complete() says so. Later results are
    // dropped (false).
    bool deliver(int worker, int tile, const std::function<void()>& keep = nullptr);
    // `worker` stopped rendering: the tiles it still held go back to the queue unless
    // another worker (not dropped) holds them too. Returns how many it held.
    int giveBack(int worker);

    // The deadline in force for `worker`'s tiles, in seconds.
    double deadline(int worker) const;
    // The deadline of a worker past its start-up (no kFirstTileSeconds), in seconds: how long
    // rank 0 lets a rank stay silent, heartbeats included, whatever it is doing.
    double usualDeadline() const;
    // Replaces the deadline of every tile (--rank-timeout); seconds > 0.
    void setDeadline(double seconds);
    // A late tile: who holds it, which, and for how long.
    struct Late {
        int worker;
        TileRect tile;
        double heldSeconds, deadlineSeconds;
    };
    // The workers (not yet dropped) holding a tile past its deadline, one entry each.
    std::vector<Late> lateWorkers() const;
    // No more tiles for `worker`; the tiles no other worker holds go to the others first.
    // Returns how many.
    int drop(int worker);
    bool dropped(int worker) const;

    // Admission closed and every tile done.
    bool complete() const;
    // Whether handOut(worker, 1) would give a tile now.
    bool anyToHandOut(int worker) const;
    double fractionDone() const;
    int tileCount() const;
    int tilesDone() const;
    TileRect tile(int index) const;
    // The index of the tile with this rectangle, if it is one of the frame's.
    std::optional<int> indexOf(const TileRect& rect) const;

    static double steadySeconds();

private:
    enum class State { Queued, HandedOut, Done };
    struct Claim {
        int worker;
        double since;  // when the tile was handed to it
    };
    struct WorkerRecord {
        bool dropped = false;
        std::optional<double> firstDelivery;
    };
    WorkerRecord& record(int worker);
    const WorkerRecord* findRecord(int worker) const;
    std::optional<int> nextFor(int worker, Copies copies) const;  // under mutex_
    std::optional<int> copyFor(int worker) const;                 // under mutex_
    bool holds(int tile, int worker) const;
    bool heldByLiveWorker(size_t tile) const;
    double deadlineLocked(int worker) const;
    double usualDeadlineLocked() const;
    double heldSeconds(const Claim& claim, double now) const;
    void requeue(int tile);

    mutable std::mutex mutex_;
    Clock clock_;
    std::optional<TileGrid> grid_;            // when the tiles are a grid's: indexOf by arithmetic
    std::vector<TileRect> tiles_;
    std::vector<State> state_;
    std::vector<std::vector<Claim>> claims_;  // the workers holding each handed-out tile
    std::deque<int> givenBack_;               // tiles of failed/dropped workers, before fresh ones
    std::vector<WorkerRecord> workers_;       // by worker, grown as workers appear
    bool admissionClosed_ = false;
    int nextFresh_ = 0, done_ = 0;
    double slowestTile_ = 0;                  // seconds
    std::optional<double> fixedDeadline_;
};

}  // namespace ray
