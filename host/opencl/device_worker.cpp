#include "opencl/device_worker.h"

#include <algorithm>
#include <deque>
#include <optional>
#include <vector>

#include "opencl/kernel_arguments.h"
#include "opencl/kernel_build.h"
#include "render/device_error.h"

namespace ray::engine {

namespace {

class DeviceWorker {
public:
    DeviceWorker(Frame& frame, DeviceSlot& slot)
        : frame_(frame), slot_(slot), index_(slot.index), failAfterTiles_(slot.hooks.failDevice.forDevice(index_)),
          hangAfterLaunches_(slot.hooks.hangDevice.forDevice(index_)) {}

    void run(cl::Kernel& kernel) {
        auto start = Clock::now();
        bool started = false;
        while (true) {
            if (failAfterTiles_ && finished_ >= *failAfterTiles_)
                throw DeviceError(slot_.device.description() + ": failed on purpose (RAY_TEST_FAIL_DEVICE)");
            while (inFlight_.size() < kTilesInFlight) {
                std::optional<int> tile = acquire();
                if (!tile) break;
                if (!started) start = Clock::now(), started = true;
                launch(kernel, *tile);
            }
            if (inFlight_.empty()) {
                std::unique_lock lock(frame_.mutex);
                if (!taking()) break;
                if (frame_.cancelled() || frame_.allDone()) break;
                frame_.changed.wait_for(lock, std::chrono::milliseconds(50));
                continue;
            }
            finishOldest();
            busySeconds_ = secondsSince(start);
        }
        std::lock_guard lock(frame_.mutex);
        Frame::Participant& p = frame_.devices[size_t(index_)];
        slot_.slowestTileSeconds = p.slowestTileSeconds;
        p.busySeconds = busySeconds_;
        if (p.part == Frame::Part::Rendering) p.part = Frame::Part::Left;
        frame_.changed.notify_all();
    }

private:
    struct Launch {
        int tile;
        size_t output;        // index in slot_.outputs
        TileEntries entries;  // what it writes and reads back
        cl::Event read;       // the last of its reads back: done once the tile is on the host
    };

    // Under the frame's lock: the frame is open and this device still part of it.
    bool taking() const { return !frame_.closed && frame_.devices[size_t(index_)].part == Frame::Part::Rendering; }

    // The next tile for this device: one given back, else a fresh one (from the source when
    // the frame has one), else (when this device is idle) a copy of one still pending on
    // another device.
    std::optional<int> acquire() {
        std::unique_lock lock(frame_.mutex);
        if (!taking() || frame_.cancelled()) return std::nullopt;
        if (auto tile = take(TileScheduler::Copies::None)) return tile;
        if (frame_.source && !frame_.sourceDone) {
            ++frame_.sourceCallers;
            lock.unlock();
            TileRect rect;
            bool more = frame_.source->next(rect);  // may block (a distributed source)
            lock.lock();
            --frame_.sourceCallers;
            frame_.changed.notify_all();
            if (more) {
                frame_.scheduler->admit(rect);
            } else if (!frame_.sourceDone) {
                frame_.sourceDone = true;
                frame_.scheduler->closeAdmission();
            }
            if (auto tile = take(TileScheduler::Copies::None)) return tile;
        }
        if (!inFlight_.empty()) return std::nullopt;
        return take(TileScheduler::Copies::Allowed);  // the end of the frame
    }

    std::optional<int> take(TileScheduler::Copies copies) {
        const std::vector<int> tiles = frame_.scheduler->handOut(index_, 1, copies);
        if (tiles.empty()) return std::nullopt;
        frame_.devices[size_t(index_)].flights.push_back({tiles.front(), Clock::now()});
        return tiles.front();
    }

    // The launch's work-items: a pixel each, or on the packet path a work-group for each
    // compute unit, which take the tile's blocks from the queue (cl/kernel.cl).
    cl::NDRange globalSize(const TileRect& rect) const {
        constexpr size_t group = kWorkGroupSide;
        if (slot_.variant.lanes > 1) return cl::NDRange(group, group * std::max<size_t>(1, slot_.device.computeUnits));
        auto roundUp = [](int n) { return (size_t(n) + group - 1) / group * group; };
        return cl::NDRange(roundUp(rect.width), roundUp(rect.height));
    }

    void launch(cl::Kernel& kernel, int tile) {
        const TileRect rect = frame_.scheduler->tile(tile);
        gpu::RayRenderParams params = frame_.params;
        params.tile = {rect.x, rect.y, rect.width, rect.height};
        // At most kTilesInFlight launches, finished in order: this output's last user is done.
        const size_t output = launches_++ % kTilesInFlight;
        DeviceSlot::TileOutput& out = slot_.outputs[output];
        const TileEntries entries = tileEntries(rect.width, rect.height, slot_.variant.lanes);
        slot_.sizeTileOutput(out, entries);  // a no-op for the frame's tiles, sized at prepareDevice
        // Arguments are captured at enqueue time.
        kernel.setArg(kernel_argument::kParams, sizeof(params), &params);
        kernel.setArg(kernel_argument::kTileColors, out.colors);
        kernel.setArg(kernel_argument::kTileRayCounts, out.counts);
        Launch l{tile, output, entries, {}};
        slot_.queue.enqueueNDRangeKernel(kernel, cl::NullRange, globalSize(rect),
                                         cl::NDRange(kWorkGroupSide, kWorkGroupSide), hangHook());
        // The tile's reads go into the queue right behind its kernel, ahead of the launches
        // after it. A read enqueued once the kernel was done came after them all in the
        // in-order queue: the device ran dry before every tile came back, and waited idle
        // while the host pasted it and launched the next.
        slot_.queue.enqueueReadBuffer(out.colors, CL_FALSE, 0, entries.pixels * sizeof(cl_float4), out.hostColors.data());
        slot_.queue.enqueueReadBuffer(out.counts, CL_FALSE, 0, entries.rayCounts * sizeof(cl_uint4),
                                      out.hostCounts.data(), nullptr, &l.read);
        slot_.queue.flush();
        inFlight_.push_back(l);
    }

    // The test hook hangDevice (RAY_TEST_HANG_DEVICE): the launches after its first n wait for
    // an event that is never set, as on a hung driver, and so does all that is queued after
    // them (the queue is in order): the device answers n tiles and its thread then blocks in
    // clWaitForEvents, for good. Called with this launch counted in launches_.
    const std::vector<cl::Event>* hangHook() {
        if (!hangAfterLaunches_ || launches_ <= size_t(*hangAfterLaunches_)) return nullptr;
        if (!slot_.neverSet) slot_.neverSet = cl::UserEvent(slot_.context);
        hangingOn_ = {*slot_.neverSet};
        return &hangingOn_;
    }

    // Waits for the oldest launch, reads its tile back and keeps it unless another device
    // finished it first.
    void finishOldest() {
        Launch l = inFlight_.front();
        l.read.wait();
        const TileRect rect = frame_.scheduler->tile(l.tile);
        const size_t n = l.entries.pixels;
        const DeviceSlot::TileOutput& out = slot_.outputs[l.output];
        const std::vector<cl_float4>& rgba = out.hostColors;
        const std::vector<cl_uint4>& rays = out.hostCounts;
        inFlight_.pop_front();

        FinishedTile result;
        result.rect = rect;
        result.device = index_;
        rgb_.resize(n * 3);
        for (size_t p = 0; p < n; ++p)
            for (int c = 0; c < 3; ++c) rgb_[p * 3 + size_t(c)] = rgba[p].s[c];
        for (size_t e = 0; e < l.entries.rayCounts; ++e) {
            result.primaryRays += rays[e].s[0];
            result.shadowRays += rays[e].s[1];
            result.secondaryRays += rays[e].s[2];
        }
        result.rgb = rgb_.data();
        keep(l.tile, result);
    }

    // The device's answer: its tile time, then the tile unless another device was first.
    void answered(Frame::Participant& p, Clock::time_point now) {
        if (p.flights.empty()) return;  // dropped as hung: its tiles were taken back
        Frame::Flight f = p.flights.front();
        p.flights.pop_front();
        if (!p.warm) {
            p.warm = true;  // the first tile also compiled the program for the launch: no measure
            auto found = slot_.programs.find(kernelFrames(frame_.settings.maxDepth));
            if (found != slot_.programs.end()) found->second.warm = true;
        } else {
            double seconds = std::chrono::duration<double>(now - std::max(f.launched, p.lastAnswer)).count();
            p.slowestTileSeconds = std::max(p.slowestTileSeconds, seconds);
            frame_.slowestTileSeconds = std::max(frame_.slowestTileSeconds, seconds);
        }
        p.lastAnswer = now;
    }

    void keep(int tile, const FinishedTile& result) {
        const Clock::time_point now = Clock::now();
        std::lock_guard lock(frame_.mutex);
        if (frame_.closed) return;
        answered(frame_.devices[size_t(index_)], now);
        const TileRect& r = result.rect;
        const bool first = frame_.scheduler->deliver(index_, tile, [&] {
            if (frame_.bytes)
                pasteTile(*frame_.bytes, r, result.rgb);
            else
                pasteTile(*frame_.image, r, result.rgb);
        });
        // The engine's thread and the devices with no tile in flight wait for the frame's
        // end (Frame::over, allDone): a tile kept before then changes nothing they wait on,
        // and waking the engine for each took a core from the device's threads (PoCL on 2
        // cores: a context switch a tile). Its deadlines only move later meanwhile.
        if (frame_.allDone()) frame_.changed.notify_all();
        if (!first) return;  // a copy, rendered at the end of the frame: another device was first
        ++finished_;
        RenderStats& s = *frame_.stats;
        s.primaryRays += result.primaryRays;
        s.shadowRays += result.shadowRays;
        s.secondaryRays += result.secondaryRays;
        DeviceStats& d = s.devices[size_t(index_)];
        ++d.tiles;
        d.kernelPrivateBytes = slot_.programs.at(kernelFrames(frame_.settings.maxDepth)).privateBytes;
        d.pixels += uint64_t(r.width) * uint64_t(r.height);
        d.rays += result.primaryRays + result.shadowRays + result.secondaryRays;
        frame_.pixelsDone += uint64_t(r.width) * uint64_t(r.height);
        if (frame_.request->onTile) frame_.request->onTile(result);
        if (frame_.request->progress && frame_.pixelsTotal > 0)
            frame_.request->progress(std::min(1.0, double(frame_.pixelsDone) / double(frame_.pixelsTotal)));
    }

    Frame& frame_;
    DeviceSlot& slot_;
    int index_;
    std::optional<int> failAfterTiles_, hangAfterLaunches_;  // the test hooks failDevice, hangDevice
    std::deque<Launch> inFlight_;
    std::vector<cl::Event> hangingOn_;
    std::vector<float> rgb_;  // the tile being kept, as FinishedTile has it
    size_t launches_ = 0;
    int finished_ = 0;  // tiles kept
    double busySeconds_ = 0;
};

}  // namespace

void renderTiles(Frame& frame, DeviceSlot& slot, cl::Kernel& kernel) { DeviceWorker(frame, slot).run(kernel); }

}  // namespace ray::engine
