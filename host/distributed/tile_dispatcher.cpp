#include "distributed/tile_dispatcher.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

namespace ray {

TileDispatcher::TileDispatcher(int width, int height, int tileSide, Clock clock)
    : clock_(std::move(clock)), grid_(width, height, tileSide), image_(width, height),
      state_(size_t(grid_.count()), State::Queued), claims_(size_t(grid_.count())) {}

double TileDispatcher::steadySeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

TileDispatcher::RankRecord& TileDispatcher::record(int rank) {
    if (size_t(rank) >= ranks_.size()) ranks_.resize(size_t(rank) + 1);
    return ranks_[size_t(rank)];
}

const TileDispatcher::RankRecord* TileDispatcher::findRecord(int rank) const {
    return size_t(rank) < ranks_.size() ? &ranks_[size_t(rank)] : nullptr;
}

bool TileDispatcher::holds(int tile, int rank) const {
    const std::vector<Claim>& claims = claims_[size_t(tile)];
    return std::any_of(claims.begin(), claims.end(), [rank](const Claim& c) { return c.rank == rank; });
}

// The tile handOut would give `rank` next: given back, fresh, else the pending tile (not
// already the rank's) with the fewest live ranks on it, the longest held of those.
std::optional<int> TileDispatcher::nextFor(int rank) const {
    const RankRecord* r = findRecord(rank);
    if (r && r->dropped) return std::nullopt;
    for (int tile : givenBack_)
        if (!holds(tile, rank)) return tile;
    if (nextFresh_ < grid_.count()) return nextFresh_;
    std::optional<int> best;
    size_t bestHolders = 0;
    double bestSince = 0;
    for (size_t t = 0; t < state_.size(); ++t) {
        if (state_[t] != State::HandedOut || holds(int(t), rank)) continue;
        size_t holders = 0;
        double since = 0;
        for (const Claim& c : claims_[t]) {
            const RankRecord* holder = findRecord(c.rank);
            if (holder && holder->dropped) continue;
            if (holders++ == 0 || c.since < since) since = c.since;
        }
        if (!best || holders < bestHolders || (holders == bestHolders && since < bestSince)) {
            best = int(t);
            bestHolders = holders;
            bestSince = since;
        }
    }
    return best;
}

std::vector<TileRect> TileDispatcher::handOut(int rank, int count) {
    std::lock_guard lock(mutex_);
    std::vector<TileRect> tiles;
    const double now = clock_();
    while (int(tiles.size()) < count) {
        std::optional<int> index = nextFor(rank);
        if (!index) break;
        if (*index == nextFresh_) ++nextFresh_;
        else if (auto it = std::find(givenBack_.begin(), givenBack_.end(), *index); it != givenBack_.end())
            givenBack_.erase(it);
        state_[size_t(*index)] = State::HandedOut;
        claims_[size_t(*index)].push_back({rank, now});
        tiles.push_back(grid_.tile(*index));
    }
    record(rank);
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
    const double now = clock_();
    RankRecord& from = record(rank);
    // The tile time, from which the deadlines follow (a rank's first delivery only starts
    // its clock: before it, the rank was starting up; a dropped rank's late tile would
    // stretch every deadline by its hang).
    for (const Claim& c : claims_[size_t(index)])
        if (c.rank == rank && from.firstDelivery && !from.dropped)
            slowestTile_ = std::max(slowestTile_, heldSeconds(c, now));
    if (!from.firstDelivery) from.firstDelivery = now;
    if (state_[size_t(index)] == State::Done) return false;
    // A tile given back by a failed or dropped rank and then delivered late by it anyway:
    // keep the result and take it off the queue.
    if (auto it = std::find(givenBack_.begin(), givenBack_.end(), index); it != givenBack_.end()) givenBack_.erase(it);
    pasteTile(image_, rect, rgb);
    state_[size_t(index)] = State::Done;
    claims_[size_t(index)].clear();
    ++done_;
    return true;
}

// Back to the front of the queue (given back tiles go out before fresh ones).
void TileDispatcher::requeue(int tile) {
    state_[size_t(tile)] = State::Queued;
    givenBack_.push_back(tile);
}

int TileDispatcher::giveBack(int rank) {
    std::lock_guard lock(mutex_);
    int count = 0;
    for (size_t t = 0; t < state_.size(); ++t) {
        if (state_[t] != State::HandedOut) continue;
        std::vector<Claim>& claims = claims_[t];
        const auto removed = std::remove_if(claims.begin(), claims.end(), [rank](const Claim& c) { return c.rank == rank; });
        if (removed == claims.end()) continue;
        claims.erase(removed, claims.end());
        ++count;
        if (claims.empty()) requeue(int(t));
    }
    return count;
}

double TileDispatcher::heldSeconds(const Claim& claim, double now) const {
    const RankRecord* r = findRecord(claim.rank);
    const double start = r && r->firstDelivery ? std::max(claim.since, *r->firstDelivery) : claim.since;
    return now - start;
}

double TileDispatcher::deadlineLocked(int rank) const {
    if (fixedDeadline_) return *fixedDeadline_;
    const double fromTiles = std::max(kDeadlineFloorSeconds, kSlowestTileFactor * slowestTile_);
    const RankRecord* r = findRecord(rank);
    return r && r->firstDelivery ? fromTiles : std::max(kFirstTileSeconds, fromTiles);
}

double TileDispatcher::deadline(int rank) const {
    std::lock_guard lock(mutex_);
    return deadlineLocked(rank);
}

void TileDispatcher::setDeadline(double seconds) {
    std::lock_guard lock(mutex_);
    fixedDeadline_ = seconds;
}

std::vector<TileDispatcher::Late> TileDispatcher::lateRanks() const {
    std::lock_guard lock(mutex_);
    const double now = clock_();
    std::vector<Late> late;
    for (size_t t = 0; t < state_.size(); ++t) {
        if (state_[t] != State::HandedOut) continue;
        for (const Claim& c : claims_[t]) {
            const RankRecord* r = findRecord(c.rank);
            if ((r && r->dropped) ||
                std::any_of(late.begin(), late.end(), [&](const Late& l) { return l.rank == c.rank; }))
                continue;
            const double held = heldSeconds(c, now), limit = deadlineLocked(c.rank);
            if (held > limit) late.push_back({c.rank, grid_.tile(int(t)), held, limit});
        }
    }
    return late;
}

int TileDispatcher::drop(int rank) {
    std::lock_guard lock(mutex_);
    record(rank).dropped = true;
    int count = 0;
    for (size_t t = 0; t < state_.size(); ++t) {
        if (state_[t] != State::HandedOut || !holds(int(t), rank)) continue;
        // Its claim stays (a late result is still taken); the tile goes out again unless
        // a rank still in the frame holds it too.
        const bool othersHold = std::any_of(claims_[t].begin(), claims_[t].end(), [&](const Claim& c) {
            const RankRecord* r = findRecord(c.rank);
            return c.rank != rank && !(r && r->dropped);
        });
        if (!othersHold) {
            requeue(int(t));
            ++count;
        }
    }
    return count;
}

bool TileDispatcher::dropped(int rank) const {
    std::lock_guard lock(mutex_);
    const RankRecord* r = findRecord(rank);
    return r && r->dropped;
}

bool TileDispatcher::complete() const {
    std::lock_guard lock(mutex_);
    return done_ == grid_.count();
}

bool TileDispatcher::anyToHandOut(int rank) const {
    std::lock_guard lock(mutex_);
    return nextFor(rank).has_value();
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
