// What the ranks of a distributed render say to each other (mpi_render.h), and how the job
// ends: the messages by tag and their encoding, the heartbeat, rank 0's decisions, and the
// ways out of the job (MPI_Abort by rank 0, a worker waiting to be ended, an interrupt).
// Only each rank's main thread calls these (MPI_THREAD_FUNNELED).
#pragma once

#include <chrono>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "render/frame_source.h"
#include "render/render_stats.h"
#include "render/tiles.h"

namespace ray::mpi {

using Clock = std::chrono::steady_clock;
using Json = nlohmann::json;

// The messages of a distributed frame, by tag. W is a worker rank (1..N-1), 0 rank 0.
enum Tag : int {
    kRequest = 1,  // W -> 0: int, how many more tiles W's devices wait for
    kTiles,        // 0 -> W: 4 ints (x, y, width, height) a tile; fewer tiles than asked: no more
    kResult,       // W -> 0: a TileResultHeader, then width x height x 3 floats (linear RGB)
    kFinished,     // W -> 0: JSON, W's statistics (and why its devices failed, if they did)
    kEnd,          // 0 -> W: a Decision, the exit code: the frame is over
    kAlive,        // W -> 0: empty, a heartbeat: W's message loop runs (kHeartbeatSeconds)
    kHello,        // W -> 0: JSON, W's start-up done: its outcome, fingerprint and host
    kStart,        // 0 -> W: a Decision, 0: render; else the exit code every rank ends with
};

// Rank 0's word to a worker on how the job goes on (kStart) or ends (kEnd).
struct Decision {
    int code = 0;        // kStart: 0 to render, else the exit code; kEnd: the exit code
    int byAbort = 0;     // 1: rank 0 ends the job with MPI_Abort, a rank having stopped answering
};
static_assert(sizeof(Decision) == 2 * sizeof(int), "a Decision is sent as two MPI_INTs");

// A worker that has sent nothing for this long sends a heartbeat, from its message loop,
// which never waits on the engine: it goes on while the rank's kernel compiles or a long
// tile renders. Rank 0 can so tell a rank that is slow (it answers) from one that is
// stopped or wedged (silent for the usual deadline, 10 s or more: dropped, whatever it was
// doing), instead of waiting for a first result for kFirstTileSeconds (120 s).
constexpr double kHeartbeatSeconds = 1;

struct TileResultHeader {
    int32_t x, y, width, height, device, reserved;
    uint64_t primaryRays, shadowRays, secondaryRays;
};
static_assert(sizeof(TileResultHeader) == 48, "the result header is sent as bytes between hosts of one kind");

// A polling loop's pause when nothing happened: blocking MPI calls spin a core, which
// would halve a 2-core rank's render; 0.2 ms adds little to a tile of tens of milliseconds.
void idle();

// SIGINT or SIGTERM came (mpirun forwards Ctrl-C as SIGTERM to every rank).
bool interrupted();

// --- Messages.

void sendHeartbeat();
void sendText(const std::string& text, int to, int tag);
// Waits for a text message of `tag` from `from` (MPI_ANY_SOURCE: any rank).
std::string receiveText(int from, int tag);

// kTiles: rank 0's answer to a request; returns the bytes sent.
size_t sendTiles(const std::vector<TileRect>& tiles, int to);
// A worker's receipt of it.
std::vector<TileRect> receiveTiles();

// kResult: a finished tile as the message a worker sends.
std::vector<char> tileResultMessage(const FinishedTile& tile);

// kFinished: a rank's statistics as rank 0 merges them (its devices' shares and set-up
// times; the rays rank 0 counts from the tiles it keeps), and the merge.
Json statsToMessage(const RenderStats& frame, double loadSeconds, const std::string& failure);
void mergeRankStats(RenderStats& stats, int rank, const Json& message);

// kStart, kEnd: rank 0's decision, and a worker's wait for it, which returns its exit code;
// it never returns when the job ends by MPI_Abort (awaitAbort).
void sendDecision(const Decision& decision, int rank, Tag tag);
int awaitDecision(Tag tag);

// --- Ending the job.

// A job whose image was written whole, but that rank 0 ended (MPI_Abort) because a rank
// stopped answering: mpirun would otherwise wait for it in MPI_Finalize forever.
constexpr int kExitRankAbandoned = 4;

// Ends every rank: an error that leaves the frame's state unknown.
[[noreturn]] void abortAll(int rank, const std::string& message);

// After SIGINT/SIGTERM (mpirun kills the ranks left a few seconds after it forwards Ctrl-C):
// leave at once, without MPI_Finalize, which waits for ranks that may be gone.
[[noreturn]] void leaveInterrupted();

// A worker told that rank 0 ends the job with MPI_Abort waits to be ended (see the .cpp).
[[noreturn]] void awaitAbort(int code);

// Rank 0, the job over for the ranks that answer (the image written, or failed for its own
// reason, or the start-up refused): ends those that never answered with MPI_Abort, which
// makes mpirun end every rank and exit with `code` (a success becomes kExitRankAbandoned).
// `abortDelaySeconds` (a test hook, 0 otherwise) delays the abort, so that the workers told
// to wait for it surely do.
[[noreturn]] void endJobWithout(const std::vector<int>& silent, int code, const std::vector<std::string>& hosts,
                                bool imageWritten, double abortDelaySeconds);

// "rank 2 (host h)"; a rank silent since the start-up has no known host.
std::string rankName(int rank, const std::vector<std::string>& hosts);
// "1.5 s", for the messages.
std::string formatSeconds(double seconds);

}  // namespace ray::mpi
