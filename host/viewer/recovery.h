// Unsaved edits kept outside the scene's folder, so that a `ray view` stopped or killed
// before a save loses none of them (docs/user-guide.md, "Unsaved edits are kept").
//
// While a scene has unsaved edits the viewer keeps a copy of its document (the text a save
// would write) in the user's state folder, $XDG_STATE_HOME/ray/recovery/ (by default
// ~/.local/state/ray/recovery/; the folder mode 700, its files 600), never beside the
// scene: its folder may be shared, synced or read-only, and the copy is no file of the
// user's. The copy is written a short while after each edit (RecoveryKeeper's thread: off
// the request and outside the viewer's lock), at once when the viewer is stopped by a
// signal, and removed when the edits are saved or undone.
//
// One file a viewer run: <key>-<start time>-<pid>.ray-recovery, where key is a hash of the
// scene's absolute path (two viewers of one scene never replace each other's copy). Its
// first line is a JSON header: the scene's path, when the copy was written, the scene
// file's size, time and hash when the viewer read it (so that an offer can say the scene
// changed since), and the document's length and hash; the document's bytes follow, exactly.
// A recovery file is read only when it is a regular file (no link, FIFO or device) of a size
// a scene can justify (kMaxRecoveryBytes) whose header and length and hash agree.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace ray {

// A recovery file that cannot be read or written: the message names it and says why.
struct RecoveryError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The largest recovery file read: the document of the largest scene the viewer can hold
// (a flat scene of millions of primitives) is well under it; anything bigger is not one.
constexpr std::uintmax_t kMaxRecoveryBytes = std::uintmax_t(1) << 30;
// How long after an edit its copy is written: a drag's or a colour picker's many edits are
// one write, and a copy is never older than this (and the write) when the viewer dies.
constexpr std::chrono::milliseconds kRecoveryDelay{1000};

// $XDG_STATE_HOME/ray/recovery when XDG_STATE_HOME is an absolute path (the XDG base
// directory rules ignore a relative one), else $HOME/.local/state/ray/recovery, else the
// home folder in the password database's; nullopt when there is no home folder at all.
std::optional<std::filesystem::path> recoveryFolder();

// The scene's path as the recovery names it: absolute, links and "..": resolved.
std::filesystem::path sceneIdentity(const std::filesystem::path& scene);

// What the scene file was when the viewer read it.
struct SceneFileStamp {
    bool exists = false;
    std::uintmax_t size = 0;
    int64_t mtimeNs = 0;
    std::string hash;  // FNV-1a 64 of its bytes, hex
};
SceneFileStamp stampOf(const std::filesystem::path& scene);
bool operator==(const SceneFileStamp& a, const SceneFileStamp& b);

// A recovery file's header, and its document once read whole.
struct Recovery {
    std::filesystem::path file;   // the recovery file
    std::string scene;            // the scene it belongs to (sceneIdentity)
    int64_t writtenUnix = 0;      // when it was written, seconds since 1970
    std::string writtenText;      // the same, local time, "2026-12-07 16:40:12"
    int pid = 0;                  // the viewer that wrote it
    SceneFileStamp sceneWhenRead;
    std::string document;
};

// Reads and checks a recovery file (see above). Throws RecoveryError.
Recovery readRecovery(const std::filesystem::path& file);

// The recoveries of `scene` in `folder`, newest first, but `except` (the viewer's own).
// A file that is not a readable recovery is passed over, `warn` told why.
std::vector<Recovery> findRecoveries(const std::filesystem::path& folder, const std::filesystem::path& scene,
                                     const std::function<void(const std::string&)>& warn,
                                     const std::filesystem::path& except = {});

// Whether the scene file on disk is no longer what the recovery's edits were made to.
bool sceneChangedSince(const Recovery& recovery, const std::filesystem::path& scene);

// Removes a recovery file; a file already gone is not an error. Throws RecoveryError.
void removeRecovery(const std::filesystem::path& file);

// The recovery folder made (mode 700, and its parents), or checked: a folder of the user's,
// not a link. Throws RecoveryError.
void prepareRecoveryFolder(const std::filesystem::path& folder);

// Writes a recovery of `scene` (a header, then `document`) to `file` atomically, mode 600.
// Throws RecoveryError.
void writeRecovery(const std::filesystem::path& file, const std::filesystem::path& scene,
                   const SceneFileStamp& sceneWhenRead, const std::string& document);

// One viewer run's recovery copy, kept by a thread of its own.
class RecoveryKeeper {
public:
    // What the keeper asks when it is to write: the document's text while it has unsaved
    // edits, nullopt when it has none (then the copy is removed); throws RecoveryError when
    // the text cannot be made. Called on the keeper's thread, or on the stop signal's; takes
    // the viewer's lock itself.
    using Snapshot = std::function<std::optional<std::string>()>;

    // `folder`: where copies go (recoveryFolder()); `scene`: the scene file.
    RecoveryKeeper(std::filesystem::path folder, const std::filesystem::path& scene, Snapshot snapshot,
                   std::function<void(const std::string&)> log);
    ~RecoveryKeeper();
    RecoveryKeeper(const RecoveryKeeper&) = delete;
    RecoveryKeeper& operator=(const RecoveryKeeper&) = delete;

    // The document changed (an edit, undo, redo, save): its copy is written or removed
    // after kRecoveryDelay, or at once when `now` (a save: the copy goes with the edits).
    void changed(bool now = false);
    // The scene file was read or written again: the next copy records it as it is now.
    void sceneRead();
    // `file`, a recovery this viewer restored, is removed once the viewer's own copy of
    // the same edits is written (or the edits saved): never a moment without one.
    void replaces(const std::filesystem::path& file);
    // `document`, edits the viewer set aside (the scene file changed on disk and was loaded
    // again over them), is kept for good in this run's file, for the next viewer to offer;
    // later edits are kept in a new file. Returns the file it is kept in.
    std::filesystem::path setAside(std::string document);
    // What a write did: whether there were unsaved edits, the file they are in, or why not.
    struct Kept {
        bool unsaved = false;
        std::filesystem::path file;
        std::string error;
    };
    // Writes the copy now, on this thread (the viewer stops).
    Kept keepNow();
    // Ends the thread, after writing what is due.
    void stop();

    // This run's recovery file (which may not exist).
    std::filesystem::path file() const;

private:
    void run();
    // Writes or removes the copy as the snapshot says.
    Kept settle();
    void writeSetAside();
    std::filesystem::path fileName(int generation) const;

    const std::filesystem::path folder_;
    const std::filesystem::path scene_;
    const Snapshot snapshot_;
    const std::function<void(const std::string&)> log_;
    const std::string baseName_;  // <key>-<start time>-<pid>
    mutable std::mutex mutex_;  // the keeper's own: never held with the viewer's
    std::mutex writing_;        // one write at a time (the thread's, the signal's)
    std::condition_variable wake_;
    std::optional<std::chrono::steady_clock::time_point> due_;
    bool stop_ = false;
    bool stampDue_ = true;
    SceneFileStamp stamp_;
    std::filesystem::path file_;
    int generation_ = 0;  // files set aside so far
    bool failureLogged_ = false;
    std::vector<std::filesystem::path> replaced_;
    struct SetAside {
        std::filesystem::path file;
        std::string document;
        SceneFileStamp stamp;
    };
    std::vector<SetAside> setAside_;  // to be written
    std::thread thread_;
};

}  // namespace ray
