#include "distributed/mpi_protocol.h"

#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <thread>

#include "app/render_command.h"
#include "core/steady_clock.h"

namespace ray::mpi {

namespace {

// How long a worker waits for mpirun to end it after rank 0's MPI_Abort (awaitAbort).
constexpr double kAwaitAbortSeconds = 60;

}  // namespace

void idle() { std::this_thread::sleep_for(std::chrono::microseconds(200)); }

bool interrupted() { return interruptFlag()->load(); }

void sendHeartbeat() { MPI_Send(nullptr, 0, MPI_INT, 0, kAlive, MPI_COMM_WORLD); }

void sendText(const std::string& text, int to, int tag) {
    MPI_Send(text.data(), int(text.size()), MPI_CHAR, to, tag, MPI_COMM_WORLD);
}

std::string receiveText(int from, int tag) {
    MPI_Status probed;
    MPI_Probe(from, tag, MPI_COMM_WORLD, &probed);
    int length = 0;
    MPI_Get_count(&probed, MPI_CHAR, &length);
    std::string text(size_t(length), '\0');
    MPI_Recv(text.data(), length, MPI_CHAR, probed.MPI_SOURCE, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return text;
}

size_t sendTiles(const std::vector<TileRect>& tiles, int to) {
    std::vector<int> values;
    for (const TileRect& t : tiles) values.insert(values.end(), {t.x, t.y, t.width, t.height});
    MPI_Send(values.data(), int(values.size()), MPI_INT, to, kTiles, MPI_COMM_WORLD);
    return values.size() * sizeof(int);
}

std::vector<TileRect> receiveTiles() {
    MPI_Status status;
    MPI_Probe(0, kTiles, MPI_COMM_WORLD, &status);
    int ints = 0;
    MPI_Get_count(&status, MPI_INT, &ints);
    std::vector<int> values(size_t(std::max(ints, 0)));
    MPI_Recv(values.data(), ints, MPI_INT, 0, kTiles, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    std::vector<TileRect> tiles;
    for (size_t i = 0; i + 3 < values.size(); i += 4) tiles.push_back({values[i], values[i + 1], values[i + 2], values[i + 3]});
    return tiles;
}

std::vector<char> tileResultMessage(const FinishedTile& tile) {
    std::vector<char> message(sizeof(TileResultHeader) + tile.rect.pixels() * 3 * sizeof(float));
    TileResultHeader header{tile.rect.x, tile.rect.y, tile.rect.width, tile.rect.height, tile.device, 0,
                            tile.primaryRays, tile.shadowRays, tile.secondaryRays};
    std::memcpy(message.data(), &header, sizeof header);
    std::memcpy(message.data() + sizeof header, tile.rgb, tile.rect.pixels() * 3 * sizeof(float));
    return message;
}

Json statsToMessage(const RenderStats& frame, double loadSeconds, const std::string& failure) {
    Json devices = Json::array();
    for (const DeviceStats& d : frame.devices)
        devices.push_back({{"device", d.device}, {"tiles", d.tiles}, {"pixels", d.pixels}, {"rays", d.rays},
                           {"busy", d.busySeconds}, {"failed", d.failed}, {"failure", d.failure}});
    // The rays are counted by rank 0 from the tiles it keeps (TileResultHeader).
    return {{"devices", devices},
            {"load", loadSeconds},
            {"bvh", frame.bvhBuildSeconds},
            {"kernel_build", frame.kernelBuildSeconds},
            {"upload", frame.uploadSeconds},
            {"warnings", frame.warnings},
            {"failure", failure}};
}

void mergeRankStats(RenderStats& stats, int rank, const Json& m) {
    for (const Json& d : m.at("devices")) {
        DeviceStats device;
        device.device = d.at("device").get<std::string>();
        device.tiles = d.at("tiles").get<int>();
        device.pixels = d.at("pixels").get<uint64_t>();
        device.rays = d.at("rays").get<uint64_t>();
        device.busySeconds = d.at("busy").get<double>();
        device.failed = d.at("failed").get<bool>();
        device.failure = d.at("failure").get<std::string>();
        stats.devices.push_back(device);
        stats.deviceRanks.push_back(rank);
    }
    stats.bvhBuildSeconds = std::max(stats.bvhBuildSeconds, m.at("bvh").get<double>());
    stats.kernelBuildSeconds = std::max(stats.kernelBuildSeconds, m.at("kernel_build").get<double>());
    stats.uploadSeconds = std::max(stats.uploadSeconds, m.at("upload").get<double>());
    for (const Json& w : m.at("warnings")) stats.warnings.push_back("rank " + std::to_string(rank) + ": " + w.get<std::string>());
}

void sendDecision(const Decision& decision, int rank, Tag tag) {
    MPI_Send(&decision, 2, MPI_INT, rank, tag, MPI_COMM_WORLD);
}

int awaitDecision(Tag tag) {
    while (true) {
        int flag = 0;
        MPI_Iprobe(0, tag, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
        if (flag) {
            Decision decision;
            MPI_Recv(&decision, 2, MPI_INT, 0, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            if (decision.byAbort) awaitAbort(decision.code);
            return decision.code;
        }
        if (interrupted()) leaveInterrupted();
        idle();
    }
}

[[noreturn]] void abortAll(int rank, const std::string& message) {
    std::cerr << "ray: rank " << rank << ": " << message << "\n" << std::flush;
    MPI_Abort(MPI_COMM_WORLD, kExitRuntime);
    std::_Exit(kExitRuntime);
}

[[noreturn]] void leaveInterrupted() {
    std::cerr << std::flush;
    std::_Exit(interruptExitCode());
}

// Rank 0 ends the job with MPI_Abort, a rank having stopped answering: this worker waits
// for mpirun to end it (SIGTERM: leaveInterrupted) instead of calling MPI_Finalize, which
// waits for every rank, the stopped one too. Measured with Open MPI 4.1.4
// (bench/mpi_abort_race.sh: 3 ranks, the third stopped, rank 0 aborting a second later):
// with the second rank in MPI_Finalize, mpirun hung (every rank a zombie) or crashed in 9
// of 25 runs; with it waiting so, in none of 25. Should mpirun never come, the worker
// leaves without MPI_Finalize (mpirun then ends the job for a rank gone unannounced).
[[noreturn]] void awaitAbort(int code) {
    const auto start = Clock::now();
    while (secondsSince(start) < kAwaitAbortSeconds) {
        if (interrupted()) leaveInterrupted();
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    std::_Exit(code);
}

// MPI_Finalize and mpirun would wait for the silent ranks for ever.
[[noreturn]] void endJobWithout(const std::vector<int>& silent, int code, const std::vector<std::string>& hosts,
                                bool imageWritten, double abortDelaySeconds) {
    std::string names;
    for (int r : silent) names += (names.empty() ? "" : ", ") + rankName(r, hosts);
    const int exitCode = code == 0 ? kExitRankAbandoned : code;
    std::cerr << "ray: ending the job without " << names << ", which did not answer"
              << (code == 0 && imageWritten ? " (the image is written and whole)" : "") << "; exit " << exitCode
              << "\n"
              << std::flush;
    if (abortDelaySeconds > 0) std::this_thread::sleep_for(std::chrono::duration<double>(abortDelaySeconds));
    MPI_Abort(MPI_COMM_WORLD, exitCode);
    std::_Exit(exitCode);
}

std::string rankName(int rank, const std::vector<std::string>& hosts) {
    const bool known = size_t(rank) < hosts.size() && !hosts[size_t(rank)].empty();
    return "rank " + std::to_string(rank) + (known ? " (host " + hosts[size_t(rank)] + ")" : std::string());
}

std::string formatSeconds(double seconds) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f s", seconds);
    return text;
}

}  // namespace ray::mpi
