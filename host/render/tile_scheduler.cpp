#include "render/tile_scheduler.h"

#include <algorithm>
#include <chrono>

namespace ray {

TileScheduler::TileScheduler(const TileGrid& grid, Clock clock) : clock_(std::move(clock)), grid_(grid) {
    for (int i = 0; i < grid.count(); ++i) tiles_.push_back(grid.tile(i));
    state_.assign(tiles_.size(), State::Queued);
    claims_.resize(tiles_.size());
    admissionClosed_ = true;
}

TileScheduler::TileScheduler(Clock clock) : clock_(std::move(clock)) {}

double TileScheduler::steadySeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

int TileScheduler::admit(const TileRect& rect) {
    std::lock_guard lock(mutex_);
    tiles_.push_back(rect);
    state_.push_back(State::Queued);
    claims_.emplace_back();
    return int(tiles_.size()) - 1;
}

void TileScheduler::closeAdmission() {
    std::lock_guard lock(mutex_);
    admissionClosed_ = true;
}

TileScheduler::WorkerRecord& TileScheduler::record(int worker) {
    if (size_t(worker) >= workers_.size()) workers_.resize(size_t(worker) + 1);
    return workers_[size_t(worker)];
}

const TileScheduler::WorkerRecord* TileScheduler::findRecord(int worker) const {
    return size_t(worker) < workers_.size() ? &workers_[size_t(worker)] : nullptr;
}

bool TileScheduler::holds(int tile, int worker) const {
    const std::vector<Claim>& claims = claims_[size_t(tile)];
    return std::any_of(claims.begin(), claims.end(), [worker](const Claim& c) { return c.worker == worker; });
}

// The tile handOut would give `worker` next: given back, else fresh, else a copy.
std::optional<int> TileScheduler::nextFor(int worker, Copies copies) const {
    const WorkerRecord* r = findRecord(worker);
    if (r && r->dropped) return std::nullopt;
    for (int tile : givenBack_)
        if (!holds(tile, worker)) return tile;
    if (nextFresh_ < int(tiles_.size())) return nextFresh_;
    if (!admissionClosed_ || copies == Copies::None) return std::nullopt;
    return copyFor(worker);
}

// The pending tile (not already the worker's) with the fewest live workers on it, the
// longest held of those.
std::optional<int> TileScheduler::copyFor(int worker) const {
    std::optional<int> best;
    size_t bestHolders = 0;
    double bestSince = 0;
    for (size_t t = 0; t < state_.size(); ++t) {
        if (state_[t] != State::HandedOut || holds(int(t), worker)) continue;
        size_t holders = 0;
        double since = 0;
        for (const Claim& c : claims_[t]) {
            const WorkerRecord* holder = findRecord(c.worker);
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

std::vector<int> TileScheduler::handOut(int worker, int count, Copies copies) {
    std::lock_guard lock(mutex_);
    std::vector<int> tiles;
    const double now = clock_();
    while (int(tiles.size()) < count) {
        std::optional<int> index = nextFor(worker, copies);
        if (!index) break;
        if (*index == nextFresh_) ++nextFresh_;
        else if (auto it = std::find(givenBack_.begin(), givenBack_.end(), *index); it != givenBack_.end())
            givenBack_.erase(it);
        state_[size_t(*index)] = State::HandedOut;
        claims_[size_t(*index)].push_back({worker, now});
        tiles.push_back(*index);
    }
    record(worker);
    return tiles;
}

bool TileScheduler::deliver(int worker, int tile, const std::function<void()>& keep) {
    std::lock_guard lock(mutex_);
    const double now = clock_();
    WorkerRecord& from = record(worker);
    // The tile time, from which the deadlines follow (a worker's first delivery only starts
    // its clock: before it, the worker was starting up; a dropped worker's late tile would
    // stretch every deadline by its hang).
    for (const Claim& c : claims_[size_t(tile)])
        if (c.worker == worker && from.firstDelivery && !from.dropped)
            slowestTile_ = std::max(slowestTile_, heldSeconds(c, now));
    if (!from.firstDelivery) from.firstDelivery = now;
    if (state_[size_t(tile)] == State::Done) return false;
    // A tile given back by a failed or dropped worker and then delivered late by it anyway:
    // keep the result and take it off the queue.
    if (auto it = std::find(givenBack_.begin(), givenBack_.end(), tile); it != givenBack_.end()) givenBack_.erase(it);
    if (keep) keep();
    state_[size_t(tile)] = State::Done;
    claims_[size_t(tile)].clear();
    ++done_;
    return true;
}

// Whether a worker not dropped holds the tile.
bool TileScheduler::heldByLiveWorker(size_t tile) const {
    return std::any_of(claims_[tile].begin(), claims_[tile].end(), [&](const Claim& c) {
        const WorkerRecord* r = findRecord(c.worker);
        return !(r && r->dropped);
    });
}

// Back to the queue (given back tiles go out before fresh ones).
void TileScheduler::requeue(int tile) {
    state_[size_t(tile)] = State::Queued;
    givenBack_.push_back(tile);
}

int TileScheduler::giveBack(int worker) {
    std::lock_guard lock(mutex_);
    int count = 0;
    for (size_t t = 0; t < state_.size(); ++t) {
        if (state_[t] != State::HandedOut) continue;
        std::vector<Claim>& claims = claims_[t];
        const auto removed =
            std::remove_if(claims.begin(), claims.end(), [worker](const Claim& c) { return c.worker == worker; });
        if (removed == claims.end()) continue;
        claims.erase(removed, claims.end());
        ++count;
        if (!heldByLiveWorker(t)) requeue(int(t));
    }
    return count;
}

double TileScheduler::heldSeconds(const Claim& claim, double now) const {
    const WorkerRecord* r = findRecord(claim.worker);
    const double start = r && r->firstDelivery ? std::max(claim.since, *r->firstDelivery) : claim.since;
    return now - start;
}

double TileScheduler::usualDeadlineLocked() const {
    return fixedDeadline_ ? *fixedDeadline_ : std::max(kDeadlineFloorSeconds, kSlowestTileFactor * slowestTile_);
}

double TileScheduler::deadlineLocked(int worker) const {
    if (fixedDeadline_) return *fixedDeadline_;
    const WorkerRecord* r = findRecord(worker);
    return r && r->firstDelivery ? usualDeadlineLocked() : std::max(kFirstTileSeconds, usualDeadlineLocked());
}

double TileScheduler::usualDeadline() const {
    std::lock_guard lock(mutex_);
    return usualDeadlineLocked();
}

double TileScheduler::deadline(int worker) const {
    std::lock_guard lock(mutex_);
    return deadlineLocked(worker);
}

void TileScheduler::setDeadline(double seconds) {
    std::lock_guard lock(mutex_);
    fixedDeadline_ = seconds;
}

std::vector<TileScheduler::Late> TileScheduler::lateWorkers() const {
    std::lock_guard lock(mutex_);
    const double now = clock_();
    std::vector<Late> late;
    for (size_t t = 0; t < state_.size(); ++t) {
        if (state_[t] != State::HandedOut) continue;
        for (const Claim& c : claims_[t]) {
            const WorkerRecord* r = findRecord(c.worker);
            if ((r && r->dropped) ||
                std::any_of(late.begin(), late.end(), [&](const Late& l) { return l.worker == c.worker; }))
                continue;
            const double held = heldSeconds(c, now), limit = deadlineLocked(c.worker);
            if (held > limit) late.push_back({c.worker, tiles_[t], held, limit});
        }
    }
    return late;
}

int TileScheduler::drop(int worker) {
    std::lock_guard lock(mutex_);
    record(worker).dropped = true;
    int count = 0;
    for (size_t t = 0; t < state_.size(); ++t) {
        if (state_[t] != State::HandedOut || !holds(int(t), worker)) continue;
        // Its claim stays (a late result is still taken); the tile goes out again unless
        // a worker still in the frame holds it too.
        if (!heldByLiveWorker(t)) {
            requeue(int(t));
            ++count;
        }
    }
    return count;
}

bool TileScheduler::dropped(int worker) const {
    std::lock_guard lock(mutex_);
    const WorkerRecord* r = findRecord(worker);
    return r && r->dropped;
}

bool TileScheduler::complete() const {
    std::lock_guard lock(mutex_);
    return admissionClosed_ && done_ == int(tiles_.size());
}

bool TileScheduler::anyToHandOut(int worker) const {
    std::lock_guard lock(mutex_);
    return nextFor(worker, Copies::Allowed).has_value();
}

double TileScheduler::fractionDone() const {
    std::lock_guard lock(mutex_);
    return tiles_.empty() ? (admissionClosed_ ? 1.0 : 0.0) : double(done_) / double(tiles_.size());
}

int TileScheduler::tileCount() const {
    std::lock_guard lock(mutex_);
    return int(tiles_.size());
}

int TileScheduler::tilesDone() const {
    std::lock_guard lock(mutex_);
    return done_;
}

TileRect TileScheduler::tile(int index) const {
    std::lock_guard lock(mutex_);
    return tiles_[size_t(index)];
}

std::optional<int> TileScheduler::indexOf(const TileRect& rect) const {
    std::lock_guard lock(mutex_);
    if (grid_) {
        const int index = grid_->indexOf(rect);
        return index < 0 ? std::nullopt : std::optional<int>(index);
    }
    for (size_t i = 0; i < tiles_.size(); ++i) {
        const TileRect& t = tiles_[i];
        if (t.x == rect.x && t.y == rect.y && t.width == rect.width && t.height == rect.height) return int(i);
    }
    return std::nullopt;
}

}  // namespace ray
