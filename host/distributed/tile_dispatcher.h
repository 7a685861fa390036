// Rank 0's side of a distributed frame (mpi_render.h), apart from MPI so that it can be
// tested alone: the tiles it hands out on demand to the ranks (itself included), the image
// the finished tiles make, and which rank holds which tile, so that a rank whose devices
// all failed gives its tiles back to the others. Thread-safe: rank 0's device threads and
// its message loop use it at once.
#pragma once

#include <cstddef>
#include <deque>
#include <mutex>
#include <vector>

#include "image/image.h"
#include "render/tiles.h"

namespace ray {

class TileDispatcher {
public:
    TileDispatcher(int width, int height, int tileSide);

    // Up to `count` tiles for `rank`: those given back by a failed rank first, then fresh
    // ones in grid order. Empty when none is left to hand out (some may still be pending
    // on other ranks).
    std::vector<TileRect> handOut(int rank, int count);
    // A finished tile: pasted into the image unless another rank delivered it first (then
    // false, and it is dropped). Throws std::invalid_argument for a rectangle that is no
    // tile of the frame or a pixel count that does not match it (a protocol error).
    bool deliver(int rank, const TileRect& rect, const float* rgb, size_t floatCount);
    // `rank` stopped rendering: the tiles it still held go back to the queue. Returns how many.
    int giveBack(int rank);

    bool complete() const;
    bool anyToHandOut() const;
    double fractionDone() const;
    int tileCount() const { return grid_.count(); }
    int tileSide() const { return grid_.side(); }
    // The finished image (call when complete(); unrendered tiles are black).
    Image takeImage();

private:
    enum class State { Queued, HandedOut, Done };
    mutable std::mutex mutex_;
    TileGrid grid_;
    Image image_;
    std::vector<State> state_;
    std::vector<int> holder_;        // the rank holding each handed-out tile
    std::deque<int> givenBack_;      // tiles of failed ranks, handed out before fresh ones
    int nextFresh_ = 0, done_ = 0;
};

}  // namespace ray
