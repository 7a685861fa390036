#include "distributed/mpi_worker.h"

#include <mpi.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "app/render_command.h"
#include "core/steady_clock.h"
#include "distributed/mpi_protocol.h"

namespace ray::mpi {

namespace {

// The device threads' tile source on a worker: each next() waits for the main thread to
// bring a tile from rank 0.
class RemoteTiles : public TileSource {
public:
    bool next(TileRect& tile) override {
        std::unique_lock lock(mutex_);
        ++waiting_;
        while (ready_.empty() && !exhausted_ && !interrupted()) arrived_.wait_for(lock, std::chrono::milliseconds(50));
        --waiting_;
        if (ready_.empty()) return false;
        tile = ready_.front();
        ready_.pop_front();
        return true;
    }
    // How many more tiles to ask rank 0 for, `asked` being already on their way.
    int shortfall(int asked) {
        std::lock_guard lock(mutex_);
        return exhausted_ ? 0 : waiting_ - int(ready_.size()) - asked;
    }
    void arrive(const std::vector<TileRect>& tiles, bool noMore) {
        std::lock_guard lock(mutex_);
        ready_.insert(ready_.end(), tiles.begin(), tiles.end());
        exhausted_ = exhausted_ || noMore;
        arrived_.notify_all();
    }

private:
    std::mutex mutex_;
    std::condition_variable arrived_;
    std::deque<TileRect> ready_;
    int waiting_ = 0;
    bool exhausted_ = false;
};

// Finished tiles waiting for the main thread to send them, as ready-made messages.
class Outbox {
public:
    void push(const FinishedTile& tile) {
        std::vector<char> message = tileResultMessage(tile);
        std::lock_guard lock(mutex_);
        messages_.push_back(std::move(message));
    }
    std::optional<std::vector<char>> pop() {
        std::lock_guard lock(mutex_);
        if (messages_.empty()) return std::nullopt;
        std::vector<char> message = std::move(messages_.front());
        messages_.pop_front();
        return message;
    }

private:
    std::mutex mutex_;
    std::deque<std::vector<char>> messages_;
};

// The test hooks stopAfterTiles and stopAfterSeconds (stopThisRank), the seconds counted from
// the message loop's start.
class StopHook {
public:
    explicit StopHook(const TestHooks& hooks)
        : start_(Clock::now()), after_(hooks.stopAfterTiles), afterSeconds_(hooks.stopAfterSeconds) {}
    void tileSent() {
        if (after_ > 0 && ++sent_ == after_) stopThisRank();
    }
    void tick() {
        if (afterSeconds_ > 0 && secondsSince(start_) >= afterSeconds_) {
            afterSeconds_ = 0;
            stopThisRank();
        }
    }

private:
    Clock::time_point start_;
    int after_ = 0, sent_ = 0;
    double afterSeconds_ = 0;
};

}  // namespace

void stopThisRank() {
    // The moment, for the test to time rank 0 from (Unix time, seconds).
    const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    std::fprintf(stderr, "ray: test hook: this rank stops itself (SIGSTOP) at %.3f\n", now);
    std::fflush(stderr);
    raise(SIGSTOP);
}

int runWorker(Prepared& p, const TestHooks& hooks) {
    StopHook stopHook(hooks);
    RemoteTiles tiles;
    Outbox outbox;
    std::atomic<bool> rendered{false};
    RenderStats frameStats;
    std::string failure;
    beginRendering();
    std::thread render([&] {
        try {
            OpenClFrameSource frames(p.devices);
            frameStats = renderShare(frames, p, frameRequest(p, tiles, [&](const FinishedTile& tile) { outbox.push(tile); }));
        } catch (...) {
            // Every device of this rank failed: rank 0 gives its tiles to the others.
            failure = describeFailure(std::current_exception()).message;
        }
        rendered = true;
    });

    std::deque<int> requests;  // tiles asked for, by request, answers pending
    int asked = 0;
    bool finished = false;
    Clock::time_point lastSent{};  // never: the first heartbeat goes at once
    while (!finished) {
        bool active = false;
        if (int more = tiles.shortfall(asked); more > 0) {
            MPI_Send(&more, 1, MPI_INT, 0, kRequest, MPI_COMM_WORLD);
            lastSent = Clock::now();
            requests.push_back(more);
            asked += more;
            active = true;
        }
        while (auto message = outbox.pop()) {
            MPI_Send(message->data(), int(message->size()), MPI_BYTE, 0, kResult, MPI_COMM_WORLD);
            lastSent = Clock::now();
            stopHook.tileSent();
            active = true;
        }
        // Any message tells rank 0 this rank is alive; a heartbeat only after a second
        // without one (the engine may be compiling, or rendering a long tile).
        if (secondsSince(lastSent) >= kHeartbeatSeconds) {
            sendHeartbeat();
            lastSent = Clock::now();
        }
        stopHook.tick();
        int flag = 0;
        MPI_Iprobe(0, kTiles, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
        if (flag && !requests.empty()) {
            std::vector<TileRect> answer = receiveTiles();
            const int wanted = requests.front();
            requests.pop_front();
            asked -= wanted;
            tiles.arrive(answer, int(answer.size()) < wanted);
            active = true;
        }
        // The engine has returned and every tile it kept is sent: report, once the
        // answers still on their way are in (they would be no tile or a spare one).
        if (rendered && requests.empty()) {
            render.join();
            while (auto message = outbox.pop())
                MPI_Send(message->data(), int(message->size()), MPI_BYTE, 0, kResult, MPI_COMM_WORLD);
            if (interrupted()) leaveInterrupted();
            sendText(statsToMessage(frameStats, p.loadSeconds, failure).dump(), 0, kFinished);
            finished = true;
        }
        if (!active) idle();
    }
    return awaitDecision(kEnd);
}

}  // namespace ray::mpi
