#include "distributed/mpi_coordinator.h"

#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <iostream>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "app/progress.h"
#include "app/render_command.h"
#include "core/steady_clock.h"
#include "distributed/mpi_protocol.h"
#include "render/tile_scheduler.h"
#include "render/tile_side.h"

namespace ray::mpi {

namespace {

// Rank 0's ranks and the image their tiles make: the frame's tile scheduler, whose
// workers are the ranks, and the image each tile is pasted into as it is kept.
class RankTiles {
public:
    RankTiles(int width, int height, int side) : scheduler(TileGrid(width, height, side)), image_(width, height) {}

    // A finished tile from `rank`: kept (true) unless another rank delivered it first.
    // Throws std::invalid_argument for a rectangle that is no tile of the frame or a pixel
    // count that does not match it (a protocol error).
    bool deliver(int rank, const TileRect& rect, const float* rgb, size_t floatCount) {
        const std::optional<int> index = scheduler.indexOf(rect);
        if (!index)
            throw std::invalid_argument("rank " + std::to_string(rank) + " delivered a tile at (" +
                                        std::to_string(rect.x) + ", " + std::to_string(rect.y) +
                                        ") that is not one of the frame's");
        if (floatCount != rect.pixels() * 3)
            throw std::invalid_argument("rank " + std::to_string(rank) + " delivered a tile with " +
                                        std::to_string(floatCount) + " values for " + std::to_string(rect.pixels()) +
                                        " pixels");
        return scheduler.deliver(rank, *index, [&] { pasteTile(image_, rect, rgb); });
    }
    std::vector<TileRect> handOut(int rank, int count) {
        std::vector<TileRect> tiles;
        for (int index : scheduler.handOut(rank, count)) tiles.push_back(scheduler.tile(index));
        return tiles;
    }
    // The finished image (call once complete(); unrendered tiles are black).
    Image takeImage() { return std::move(image_); }

    TileScheduler scheduler;

private:
    Image image_;  // written under the scheduler's lock (deliver's keep)
};

// Rank 0's own devices take their tiles straight from the ranks' scheduler.
class RankZeroTiles : public TileSource {
public:
    explicit RankZeroTiles(RankTiles& ranks) : ranks_(ranks) {}
    bool next(TileRect& tile) override {
        std::vector<TileRect> tiles = ranks_.handOut(0, 1);
        if (tiles.empty()) return false;
        tile = tiles.front();
        return true;
    }

private:
    RankTiles& ranks_;
};

// Rank 0's own share, on its own thread: rounds of the engine until the frame is complete
// (a second round only when a failed or dropped rank's tiles came back after the first
// ended). Rank 0's tiles have no deadline: its devices are in this process, and a hung
// one is the engine's to handle.
struct LocalShare {
    std::atomic<bool> done{false};
    std::atomic<int> tilesKept{0};
    std::atomic<bool> stop{false};
    std::mutex mutex;
    std::vector<RenderStats> rounds;
    std::string failure;  // every device of rank 0 failed
};

void renderLocalShare(Prepared& p, RankTiles& ranks, LocalShare& share) {
    TileScheduler& scheduler = ranks.scheduler;
    try {
        OpenClFrameSource frames(p.devices);  // the scene packed once, for every round
        while (!share.stop && !interrupted() && !scheduler.complete()) {
            if (!scheduler.anyToHandOut(0)) {
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
                continue;
            }
            RankZeroTiles tiles(ranks);
            RenderStats round = renderShare(frames, p, frameRequest(p, tiles, [&](const FinishedTile& tile) {
                                                if (ranks.deliver(0, tile.rect, tile.rgb, tile.rect.pixels() * 3))
                                                    ++share.tilesKept;
                                            }));
            std::lock_guard lock(share.mutex);
            share.rounds.push_back(std::move(round));
        }
    } catch (...) {
        scheduler.giveBack(0);
        std::lock_guard lock(share.mutex);
        share.failure = describeFailure(std::current_exception()).message;
    }
    share.done = true;
}

// One rank's statistics from the engine's rounds on rank 0: devices summed over rounds.
RenderStats sumRounds(const std::vector<RenderStats>& rounds) {
    RenderStats total;
    for (const RenderStats& r : rounds) {
        total.primaryRays += r.primaryRays;
        total.shadowRays += r.shadowRays;
        total.secondaryRays += r.secondaryRays;
        total.bvhBuildSeconds += r.bvhBuildSeconds;
        total.kernelBuildSeconds += r.kernelBuildSeconds;
        total.uploadSeconds += r.uploadSeconds;
        total.warnings.insert(total.warnings.end(), r.warnings.begin(), r.warnings.end());
        if (total.devices.empty()) total.devices = r.devices;
        else
            for (size_t i = 0; i < r.devices.size() && i < total.devices.size(); ++i) {
                DeviceStats& d = total.devices[i];
                d.tiles += r.devices[i].tiles;
                d.pixels += r.devices[i].pixels;
                d.rays += r.devices[i].rays;
                d.busySeconds += r.devices[i].busySeconds;
                d.failed = d.failed || r.devices[i].failed;
                if (d.failure.empty()) d.failure = r.devices[i].failure;
            }
    }
    return total;
}

// How often rank 0 looks for tiles past their deadline.
constexpr double kDeadlineCheckSeconds = 0.1;

class Coordinator {
public:
    // `silentAtStart`: the workers that never finished their start-up (startCoordinator),
    // already named; they get no tiles, and the job ends without them.
    Coordinator(Prepared& p, const MpiSession& mpi, int tileSide, std::vector<std::string> hosts,
                const std::vector<int>& silentAtStart, const TestHooks& hooks)
        : p_(p), mpi_(mpi), hooks_(hooks), ranks_(p.options.settings.width, p.options.settings.height, tileSide),
          rankStats_(size_t(mpi.size)), tilesPerRank_(size_t(mpi.size), 0), abandoned_(size_t(mpi.size), false),
          hosts_(std::move(hosts)), lastHeard_(size_t(mpi.size), Clock::now()) {
        if (p.options.rankTimeout > 0) scheduler_.setDeadline(p.options.rankTimeout);
        for (int r : silentAtStart) {
            abandoned_[size_t(r)] = true;
            scheduler_.drop(r);
        }
    }

    int run() {
        ProgressBar progress(!p_.options.quiet);
        beginRendering();
        const auto start = Clock::now();
        LocalShare share;
        std::thread local([&] { renderLocalShare(p_, ranks_, share); });
        auto lastCheck = Clock::now();
        while (!interrupted()) {
            const bool handled = handleOneMessage();
            if (secondsSince(lastCheck) >= kDeadlineCheckSeconds) {
                abandonUnresponsiveRanks();
                lastCheck = Clock::now();
            }
            if (handled) continue;
            progress.update(scheduler_.fractionDone());
            // Rank 0's share ends when the frame is complete or its devices all failed.
            if (share.done && everyWorkerAccountedFor()) break;
            idle();
        }
        share.stop = true;
        local.join();
        progress.finish();
        const double renderSeconds = secondsSince(start);

        RenderedFrame result;
        result.cancelled = interrupted();
        const bool complete = scheduler_.complete();
        result.image = ranks_.takeImage();
        int code = 0;
        if (!result.cancelled && !complete) {
            std::cerr << "ray: every rank's OpenCL devices failed or stopped answering; rank 0: " << share.failure
                      << "\n";
            code = kExitRuntime;
        } else {
            result.stats = collectStats(share);
            result.stats.renderSeconds = renderSeconds;
            try {
                code = finishRender(result, p_.output, p_.options);
            } catch (...) {
                code = reportFailure(std::current_exception());
            }
        }
        if (result.cancelled) leaveInterrupted();
        std::vector<int> silent;
        for (int r = 1; r < mpi_.size; ++r)
            if (!rankStats_[size_t(r)]) silent.push_back(r);
        for (int r = 1; r < mpi_.size; ++r)
            if (rankStats_[size_t(r)]) sendDecision({code, !silent.empty()}, r, kEnd);
        if (!silent.empty())
            endJobWithout(silent, code, hosts_, !result.cancelled && complete && code == 0, hooks_.abortAfterSeconds);
        return code;
    }

private:
    std::string nameOf(int rank) const { return rankName(rank, hosts_); }

    bool everyWorkerAccountedFor() const {
        for (int r = 1; r < mpi_.size; ++r)
            if (!rankStats_[size_t(r)] && !abandoned_[size_t(r)]) return false;
        return true;
    }

    // A worker holding a tile past its deadline, or silent (not even a heartbeat) for the
    // usual deadline, is taken for hung: named, given no more tiles, its tiles to the others.
    void abandonUnresponsiveRanks() {
        for (const TileScheduler::Late& late : scheduler_.lateWorkers()) {
            if (late.worker == 0 || rankStats_[size_t(late.worker)]) continue;
            abandon(late.worker, "held its tile at (" + std::to_string(late.tile.x) + ", " + std::to_string(late.tile.y) +
                                   ") for " + formatSeconds(late.heldSeconds) + ", past its deadline of " +
                                   formatSeconds(late.deadlineSeconds));
        }
        // A worker that answers sends a heartbeat every kHeartbeatSeconds until it has sent
        // its statistics, even while its kernel compiles (its tiles then wait for their first
        // result up to kFirstTileSeconds): silence for the usual deadline, not the first
        // tile's, means it stopped, whatever it was doing. Also once the image is complete,
        // when it holds no tile that counts but its statistics are due.
        const double limit = scheduler_.usualDeadline();
        for (int r = 1; r < mpi_.size; ++r) {
            const double silence = secondsSince(lastHeard_[size_t(r)]);
            if (!rankStats_[size_t(r)] && !abandoned_[size_t(r)] && silence > limit)
                abandon(r, "sent nothing for " + formatSeconds(silence) + ", not even a heartbeat (its deadline: " +
                               formatSeconds(limit) + ")" +
                               (scheduler_.complete() ? ", and the image is complete without it" : ""));
        }
    }

    void abandon(int rank, const std::string& why) {
        abandoned_[size_t(rank)] = true;
        const int moved = scheduler_.drop(rank);
        std::cerr << "ray: warning: " << nameOf(rank) << " does not answer: it " << why << "; it gets no more tiles ("
                  << moved << " of its tiles went to the other ranks; --rank-timeout sets the deadline)\n"
                  << std::flush;
    }

private:
    // Handles the next message if one is waiting; false when none is.
    bool handleOneMessage() {
        int flag = 0;
        MPI_Status status;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
        if (!flag) return false;
        const auto start = Clock::now();
        const int from = status.MPI_SOURCE;
        lastHeard_[size_t(from)] = start;
        int bytes = 0;
        MPI_Get_count(&status, MPI_BYTE, &bytes);
        messages_ += 1;
        bytes_ += uint64_t(bytes);
        switch (status.MPI_TAG) {
            case kRequest: answerRequest(from); break;
            case kResult: receiveResult(from, bytes); break;
            case kFinished: receiveFinished(from); break;
            case kAlive: MPI_Recv(nullptr, 0, MPI_INT, from, kAlive, MPI_COMM_WORLD, MPI_STATUS_IGNORE); break;
            // A rank left out of the frame for its silent start-up, that answers after all:
            // it waits for a start that never comes, and is ended with the job.
            case kHello: receiveText(from, kHello); break;
            default: abortAll(0, "unexpected message (tag " + std::to_string(status.MPI_TAG) + ") from rank " + std::to_string(from));
        }
        dispatchSeconds_ += secondsSince(start);
        return true;
    }

    void answerRequest(int from) {
        int count = 0;
        MPI_Recv(&count, 1, MPI_INT, from, kRequest, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        bytes_ += sendTiles(ranks_.handOut(from, std::clamp(count, 0, 1024)), from);
        messages_ += 1;
    }

    // A tile message is received into floats, so that its pixels are pasted from where they
    // arrived (the header is a whole number of floats).
    void receiveResult(int from, int bytes) {
        static_assert(sizeof(TileResultHeader) % sizeof(float) == 0);
        constexpr size_t kHeaderFloats = sizeof(TileResultHeader) / sizeof(float);
        buffer_.resize((size_t(std::max(bytes, 0)) + sizeof(float) - 1) / sizeof(float));
        MPI_Recv(buffer_.data(), bytes, MPI_BYTE, from, kResult, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (size_t(bytes) < sizeof(TileResultHeader)) abortAll(0, "a short tile message from rank " + std::to_string(from));
        TileResultHeader header;
        std::memcpy(&header, buffer_.data(), sizeof header);
        const TileRect rect{header.x, header.y, header.width, header.height};
        const size_t floats = (size_t(bytes) - sizeof header) / sizeof(float);
        try {
            if (ranks_.deliver(from, rect, buffer_.data() + kHeaderFloats, floats)) {
                // The rays of the tiles kept: those of a rank that failed later count too.
                ++tilesPerRank_[size_t(from)];
                workerRays_.primaryRays += header.primaryRays;
                workerRays_.shadowRays += header.shadowRays;
                workerRays_.secondaryRays += header.secondaryRays;
            }
        } catch (const std::invalid_argument& e) {
            abortAll(0, e.what());
        }
    }

    // A worker's statistics: kept, merged in rank order at the end (collectStats).
    void receiveFinished(int from) {
        Json message;
        try {
            message = Json::parse(receiveText(from, kFinished));
        } catch (const Json::exception& e) {
            abortAll(0, "unreadable statistics from rank " + std::to_string(from) + ": " + e.what());
        }
        std::string failure = message.value("failure", "");
        if (failure.rfind("ray: ", 0) == 0) failure.erase(0, 5);
        if (!failure.empty()) {
            const int givenBack = scheduler_.giveBack(from);
            dropWarnings_.push_back("rank " + std::to_string(from) + " dropped (" + std::to_string(givenBack) +
                                    " tiles given to the others): " + failure);
        }
        rankStats_[size_t(from)] = std::move(message);
    }

    RenderStats collectStats(LocalShare& share) {
        RenderStats stats;
        std::lock_guard lock(share.mutex);
        const RenderStats own = sumRounds(share.rounds);
        rankStats_[0] = statsToMessage(own, p_.loadSeconds, share.failure);
        if (!share.failure.empty()) stats.warnings.push_back("rank 0 dropped: " + share.failure);
        for (size_t rank = 0; rank < rankStats_.size(); ++rank)
            if (rankStats_[rank]) mergeRankStats(stats, int(rank), *rankStats_[rank]);
        stats.warnings.insert(stats.warnings.end(), dropWarnings_.begin(), dropWarnings_.end());
        stats.primaryRays = own.primaryRays + workerRays_.primaryRays;
        stats.shadowRays = own.shadowRays + workerRays_.shadowRays;
        stats.secondaryRays = own.secondaryRays + workerRays_.secondaryRays;

        const RenderSettings& s = p_.options.settings;
        stats.width = s.width;
        stats.height = s.height;
        stats.depth = s.maxDepth;
        stats.samples = maxSamplesPerPixel(s);
        stats.loadSeconds = p_.loadSeconds;
        stats.device = std::to_string(mpi_.size) + " MPI ranks, " + std::to_string(stats.devices.size()) +
                       " OpenCL devices";
        DistributionStats& d = stats.distribution;
        d.ranks = mpi_.size;
        d.tiles = scheduler_.tileCount();
        d.tilesPerRank = tilesPerRank_;
        d.tilesPerRank[0] = share.tilesKept;
        d.messages = messages_;
        d.bytes = bytes_;
        d.dispatchSeconds = dispatchSeconds_;
        return stats;
    }

    Prepared& p_;
    const MpiSession& mpi_;
    const TestHooks& hooks_;
    RankTiles ranks_;
    TileScheduler& scheduler_ = ranks_.scheduler;
    std::vector<std::optional<Json>> rankStats_;  // each worker's, once it finished; rank 0's at the end
    std::vector<int> tilesPerRank_;
    std::vector<std::string> dropWarnings_;  // workers whose devices all failed
    std::vector<bool> abandoned_;            // workers taken for hung (abandonUnresponsiveRanks)
    std::vector<std::string> hosts_;         // each rank's host, for the messages
    std::vector<Clock::time_point> lastHeard_;  // each worker's latest message
    struct {
        uint64_t primaryRays = 0, shadowRays = 0, secondaryRays = 0;
    } workerRays_;  // the rays of the workers' tiles kept
    std::vector<float> buffer_;
    uint64_t messages_ = 0, bytes_ = 0;
    double dispatchSeconds_ = 0;
};

}  // namespace

int runCoordinator(Prepared& p, const MpiSession& mpi, std::vector<std::string> hosts,
                   const std::vector<int>& silentAtStart, const TestHooks& hooks) {
    return Coordinator(p, mpi, tileSideOf(p), std::move(hosts), silentAtStart, hooks).run();
}

}  // namespace ray::mpi
