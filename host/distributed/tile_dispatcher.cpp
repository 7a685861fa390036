#include "distributed/tile_dispatcher.h"

#include <stdexcept>
#include <string>

namespace ray {

TileDispatcher::TileDispatcher(int width, int height, int tileSide)
    : grid_(width, height, tileSide), image_(width, height), state_(size_t(grid_.count()), State::Queued),
      holder_(size_t(grid_.count()), -1) {}

std::vector<TileRect> TileDispatcher::handOut(int rank, int count) {
    std::lock_guard lock(mutex_);
    std::vector<TileRect> tiles;
    while (int(tiles.size()) < count) {
        int index;
        if (!givenBack_.empty()) {
            index = givenBack_.front();
            givenBack_.pop_front();
        } else if (nextFresh_ < grid_.count()) {
            index = nextFresh_++;
        } else {
            break;
        }
        state_[size_t(index)] = State::HandedOut;
        holder_[size_t(index)] = rank;
        tiles.push_back(grid_.tile(index));
    }
    return tiles;
}

bool TileDispatcher::deliver(int rank, const TileRect& rect, const float* rgb, size_t floatCount) {
    const int index = grid_.indexOf(rect);
    if (index < 0)
        throw std::invalid_argument("rank " + std::to_string(rank) + " delivered a tile at (" + std::to_string(rect.x) +
                                    ", " + std::to_string(rect.y) + ") that is not one of the frame's");
    if (floatCount != rect.pixels() * 3)
        throw std::invalid_argument("rank " + std::to_string(rank) + " delivered a tile with " +
                                    std::to_string(floatCount) + " values for " + std::to_string(rect.pixels()) +
                                    " pixels");
    std::lock_guard lock(mutex_);
    if (state_[size_t(index)] == State::Done) return false;
    // A tile given back by a failed rank and then delivered late by it anyway: keep the
    // result and take it off the queue.
    if (state_[size_t(index)] == State::Queued)
        for (auto it = givenBack_.begin(); it != givenBack_.end(); ++it)
            if (*it == index) {
                givenBack_.erase(it);
                break;
            }
    pasteTile(image_, rect, rgb);
    state_[size_t(index)] = State::Done;
    ++done_;
    return true;
}

int TileDispatcher::giveBack(int rank) {
    std::lock_guard lock(mutex_);
    int count = 0;
    for (size_t t = 0; t < state_.size(); ++t)
        if (state_[t] == State::HandedOut && holder_[t] == rank) {
            state_[t] = State::Queued;
            holder_[t] = -1;
            givenBack_.push_back(int(t));
            ++count;
        }
    return count;
}

bool TileDispatcher::complete() const {
    std::lock_guard lock(mutex_);
    return done_ == grid_.count();
}

bool TileDispatcher::anyToHandOut() const {
    std::lock_guard lock(mutex_);
    return !givenBack_.empty() || nextFresh_ < grid_.count();
}

double TileDispatcher::fractionDone() const {
    std::lock_guard lock(mutex_);
    return grid_.count() ? double(done_) / grid_.count() : 1.0;
}

Image TileDispatcher::takeImage() {
    std::lock_guard lock(mutex_);
    return std::move(image_);
}

}  // namespace ray
