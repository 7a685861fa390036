// Unsaved edits kept in the user's state folder (viewer/recovery.h).
#include "viewer/recovery.h"

#include <fcntl.h>
#include <pwd.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <utility>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/fnv1a.h"
#include "core/input_file.h"
#include "core/message_text.h"

namespace ray {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kExtension = ".ray-recovery";
constexpr int kFormat = 1;
// A header is a few hundred bytes; a longer first line is no recovery's.
constexpr size_t kMaxHeaderBytes = 64 * 1024;

std::string hexOf(uint64_t value) {
    static const char digits[] = "0123456789abcdef";
    std::string text(16, '0');
    for (int i = 15; i >= 0; --i, value >>= 4) text[size_t(i)] = digits[value & 15];
    return text;
}

// The FNV-1a hash in hex (core/fnv1a.h): names a scene's recoveries and tells when bytes changed.
std::string hashOf(std::string_view bytes) { return hexOf(fnv1a(bytes)); }

// A path as a header holds it: JSON text is UTF-8, so a path that is not has replacement
// characters in their place (the file's name, a hash of the exact path, still finds it).
std::string headerText(const fs::path& path) {
    return json::parse(json(path.string()).dump(-1, ' ', false, json::error_handler_t::replace)).get<std::string>();
}

// The start of every recovery file name of `scene`.
std::string sceneKey(const fs::path& scene) { return hashOf(sceneIdentity(scene).string()); }

std::string localTime(std::time_t when, const char* format) {
    char text[32];
    std::tm parts{};
    localtime_r(&when, &parts);
    std::strftime(text, sizeof text, format, &parts);
    return text;
}

[[noreturn]] void fail(const fs::path& file, const std::string& why) {
    throw RecoveryError("recovery file " + quotedForMessage(file.string()) + ": " + why);
}

// A descriptor that closes itself.
struct Descriptor {
    int fd = -1;
    explicit Descriptor(int f) : fd(f) {}
    ~Descriptor() {
        if (fd >= 0) ::close(fd);
    }
    Descriptor(const Descriptor&) = delete;
    Descriptor& operator=(const Descriptor&) = delete;
};

json stampJson(const SceneFileStamp& stamp) {
    return {{"exists", stamp.exists}, {"size", stamp.size}, {"mtime_ns", stamp.mtimeNs}, {"fnv1a64", stamp.hash}};
}

SceneFileStamp stampFromJson(const json& j) {
    SceneFileStamp stamp;
    stamp.exists = j.at("exists").get<bool>();
    stamp.size = j.at("size").get<std::uintmax_t>();
    stamp.mtimeNs = j.at("mtime_ns").get<int64_t>();
    stamp.hash = j.at("fnv1a64").get<std::string>();
    return stamp;
}

// Makes `folder` with mode 700 if it is not there (only the parts that are not).
void makeFolder(const fs::path& folder) {
    fs::path made;
    for (const fs::path& part : folder) {
        made /= part;
        if (::mkdir(made.c_str(), 0700) != 0 && errno != EEXIST)
            throw RecoveryError("cannot make the recovery folder " + quotedForMessage(made.string()) + " (" +
                                std::strerror(errno) + ")");
    }
}

}  // namespace

std::optional<fs::path> recoveryFolder() {
    const char* state = std::getenv("XDG_STATE_HOME");
    if (state && fs::path(state).is_absolute()) return fs::path(state) / "ray" / "recovery";
    const char* home = std::getenv("HOME");
    if (!home || !*home) {
        const passwd* user = getpwuid(geteuid());
        home = user ? user->pw_dir : nullptr;
    }
    if (!home || !*home) return std::nullopt;
    return fs::path(home) / ".local" / "state" / "ray" / "recovery";
}

fs::path sceneIdentity(const fs::path& scene) {
    std::error_code ec;
    fs::path path = fs::weakly_canonical(fs::absolute(scene, ec), ec);
    return ec ? fs::absolute(scene).lexically_normal() : path;
}

SceneFileStamp sceneFileStampOf(const fs::path& scene) {
    SceneFileStamp stamp;
    // No link is followed past the scene's own, no FIFO waited on (O_NONBLOCK), no device read.
    Descriptor file(::open(scene.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
    struct stat facts {};
    if (file.fd < 0 || ::fstat(file.fd, &facts) != 0) return stamp;
    stamp.exists = true;
    stamp.size = std::uintmax_t(facts.st_size);
    stamp.mtimeNs = int64_t(facts.st_mtim.tv_sec) * 1'000'000'000 + facts.st_mtim.tv_nsec;
    if (!S_ISREG(facts.st_mode)) return stamp;
    Fnv1a hash;
    char buffer[1 << 16];
    for (;;) {
        const ssize_t n = ::read(file.fd, buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        hash.add(buffer, size_t(n));
    }
    stamp.hash = hexOf(hash.value());
    return stamp;
}

bool operator==(const SceneFileStamp& a, const SceneFileStamp& b) {
    return a.exists == b.exists && a.size == b.size && a.mtimeNs == b.mtimeNs && a.hash == b.hash;
}

Recovery readRecovery(const fs::path& file) {
    static const InputLimit kRecoveryFile{"a recovery copy", kMaxRecoveryBytes, "more than any scene's text",
                                          /*refuseLink=*/true};
    std::string bytes;
    try {
        bytes = readInputFile(file, kRecoveryFile);
    } catch (const InputFileError& e) {
        fail(file, e.reason());
    }
    const size_t end = bytes.find('\n');
    if (end == std::string::npos || end > kMaxHeaderBytes) fail(file, "has no header line");
    Recovery recovery;
    recovery.file = file;
    try {
        const json header = json::parse(bytes.substr(0, end));
        if (header.at("ray_recovery").get<int>() != kFormat) fail(file, "is of another format version");
        recovery.scene = header.at("scene").get<std::string>();
        recovery.writtenUnix = header.at("written_unix").get<int64_t>();
        recovery.writtenText = header.at("written").get<std::string>();
        recovery.pid = header.at("pid").get<int>();
        recovery.sceneWhenRead = stampFromJson(header.at("scene_file"));
        const size_t length = header.at("document_bytes").get<size_t>();
        recovery.document = bytes.substr(end + 1);
        if (recovery.document.size() != length)
            fail(file, "is cut short: " + std::to_string(recovery.document.size()) + " of its " + std::to_string(length) +
                           " bytes of scene");
        if (hashOf(recovery.document) != header.at("document_fnv1a64").get<std::string>())
            fail(file, "does not match its own hash (damaged)");
    } catch (const json::exception& e) {
        fail(file, std::string("has a header that is not a recovery's (") + e.what() + ")");
    }
    return recovery;
}

std::vector<Recovery> findRecoveries(const fs::path& folder, const fs::path& scene,
                                     const std::function<void(const std::string&)>& warn, const fs::path& except) {
    std::vector<Recovery> found;
    std::error_code ec;
    if (!fs::is_directory(fs::symlink_status(folder, ec))) return found;
    const std::string identity = headerText(sceneIdentity(scene));
    const std::string prefix = sceneKey(scene) + "-";
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.rfind(prefix, 0) != 0 || !name.ends_with(kExtension) || it->path().filename() == except.filename())
            continue;
        try {
            Recovery recovery = readRecovery(it->path());
            if (recovery.scene == identity) found.push_back(std::move(recovery));
        } catch (const RecoveryError& e) {
            if (warn) warn(std::string(e.what()) + " (passed over)");
        }
    }
    std::sort(found.begin(), found.end(), [](const Recovery& a, const Recovery& b) {
        return a.writtenUnix != b.writtenUnix ? a.writtenUnix > b.writtenUnix : a.file > b.file;
    });
    return found;
}

bool sceneChangedSince(const Recovery& recovery, const fs::path& scene) {
    return !(sceneFileStampOf(scene) == recovery.sceneWhenRead);
}

void removeRecovery(const fs::path& file) {
    if (::unlink(file.c_str()) != 0 && errno != ENOENT) fail(file, std::string("cannot be removed (") + std::strerror(errno) + ")");
}

void prepareRecoveryFolder(const fs::path& folder) {
    makeFolder(folder);
    struct stat facts {};
    if (::lstat(folder.c_str(), &facts) != 0 || !S_ISDIR(facts.st_mode))
        throw RecoveryError("the recovery folder " + quotedForMessage(folder.string()) + " is not a folder (a link?)");
    if (facts.st_uid != geteuid())
        throw RecoveryError("the recovery folder " + quotedForMessage(folder.string()) + " belongs to another user");
    // Other users may not read the edits of a scene they cannot read.
    if ((facts.st_mode & 077) != 0 && ::chmod(folder.c_str(), 0700) != 0)
        throw RecoveryError("cannot make the recovery folder " + quotedForMessage(folder.string()) + " private (" +
                            std::strerror(errno) + ")");
}

void writeRecovery(const fs::path& file, const fs::path& scene, const SceneFileStamp& sceneWhenRead,
                   const std::string& document) {
    const std::time_t now = std::time(nullptr);
    const json header = {{"ray_recovery", kFormat},
                         {"scene", headerText(sceneIdentity(scene))},
                         {"written", localTime(now, "%Y-%m-%d %H:%M:%S")},
                         {"written_unix", int64_t(now)},
                         {"pid", int(getpid())},
                         {"scene_file", stampJson(sceneWhenRead)},
                         {"document_bytes", document.size()},
                         {"document_fnv1a64", hashOf(document)}};
    std::string bytes = header.dump();
    bytes += '\n';
    bytes += document;
    try {
        // Private before it is written, so that it never appears readable by others.
        writeFileAtomicallyVia(file, [&](const fs::path& temporary) {
            if (::chmod(temporary.c_str(), 0600) != 0)
                throw FileWriteError(quotedForMessage(temporary.string()) + " cannot be made private (" +
                                     std::strerror(errno) + ")");
            std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
            out.write(bytes.data(), std::streamsize(bytes.size()));
            out.close();
            if (!out) throw FileWriteError("cannot write " + quotedForMessage(temporary.string()) + " (" + std::strerror(errno) + ")");
        });
    } catch (const FileWriteError& e) {
        throw RecoveryError(e.what());
    }
    // Kept private whatever the writer does with the mode of a file it replaces.
    if (::chmod(file.c_str(), 0600) != 0) fail(file, std::string("cannot be made private (") + std::strerror(errno) + ")");
}

// ---- RecoveryKeeper

RecoveryKeeper::RecoveryKeeper(fs::path folder, const fs::path& scene, Snapshot snapshot,
                               std::function<void(const std::string&)> log)
    : folder_(std::move(folder)), scene_(sceneIdentity(scene)), snapshot_(std::move(snapshot)), log_(std::move(log)),
      baseName_(sceneKey(scene) + "-" + localTime(std::time(nullptr), "%Y%m%dT%H%M%S") + "-" + std::to_string(getpid())),
      file_(fileName(0)) {
    thread_ = std::thread([this] { run(); });
}

RecoveryKeeper::~RecoveryKeeper() { stop(); }

fs::path RecoveryKeeper::fileName(int generation) const {
    return folder_ / (baseName_ + (generation ? "-" + std::to_string(generation) : "") + kExtension);
}

fs::path RecoveryKeeper::file() const {
    std::lock_guard lock(mutex_);
    return file_;
}

void RecoveryKeeper::changed(bool now) {
    std::lock_guard lock(mutex_);
    const auto at = std::chrono::steady_clock::now() + (now ? std::chrono::milliseconds(0) : kRecoveryDelay);
    // The earliest wins: edits in a row (a drag) do not put the write off, so the copy is
    // never older than kRecoveryDelay.
    if (!due_ || at < *due_) due_ = at;
    wake_.notify_all();
}

void RecoveryKeeper::sceneRead() {
    std::lock_guard lock(mutex_);
    stampDue_ = true;
}

void RecoveryKeeper::replaces(const fs::path& file) {
    std::lock_guard lock(mutex_);
    replaced_.push_back(file);
}

fs::path RecoveryKeeper::setAside(std::string document) {
    std::lock_guard lock(mutex_);
    const fs::path left = file_;
    setAside_.push_back({left, std::move(document), stamp_});
    file_ = fileName(++generation_);
    due_ = std::chrono::steady_clock::now();
    wake_.notify_all();
    return left;
}

RecoveryKeeper::Kept RecoveryKeeper::keepNow() { return settle(); }

void RecoveryKeeper::stop() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
        wake_.notify_all();
    }
    if (thread_.joinable()) thread_.join();
}

void RecoveryKeeper::run() {
    std::unique_lock lock(mutex_);
    for (;;) {
        if (stop_ && due_) due_ = std::chrono::steady_clock::now();  // what is due is written before the end
        if (due_ && std::chrono::steady_clock::now() >= *due_) {
            due_.reset();
            lock.unlock();
            settle();
            lock.lock();
            continue;
        }
        if (stop_) return;
        if (due_) wake_.wait_until(lock, *due_);
        else wake_.wait(lock);
    }
}

// Set-aside edits first: the file they go to is no longer this run's current one.
void RecoveryKeeper::writeSetAside() {
    std::vector<SetAside> pending;
    {
        std::lock_guard lock(mutex_);
        pending.swap(setAside_);
    }
    for (SetAside& aside : pending) {
        try {
            prepareRecoveryFolder(folder_);
            writeRecovery(aside.file, scene_, aside.stamp, aside.document);
        } catch (const RecoveryError& e) {
            if (log_) log_(std::string("set-aside edits not kept: ") + e.what());
        }
    }
}

RecoveryKeeper::Kept RecoveryKeeper::settle() {
    std::lock_guard writing(writing_);
    writeSetAside();
    Kept kept;
    bool stampDue = false;
    std::vector<fs::path> replaced;
    try {
        const std::optional<std::string> text = snapshot_();
        kept.unsaved = text.has_value();
        {
            // Read after the snapshot: a copy set aside before it is never written over.
            std::lock_guard lock(mutex_);
            kept.file = file_;
            stampDue = std::exchange(stampDue_, false);
            replaced = replaced_;
        }
        if (text) {
            if (stampDue) stamp_ = sceneFileStampOf(scene_);
            prepareRecoveryFolder(folder_);
            writeRecovery(kept.file, scene_, stamp_, *text);
        } else {
            removeRecovery(kept.file);
        }
        for (const fs::path& file : replaced) removeRecovery(file);
        std::lock_guard lock(mutex_);
        replaced_.erase(replaced_.begin(), replaced_.begin() + std::ptrdiff_t(std::min(replaced.size(), replaced_.size())));
        failureLogged_ = false;
    } catch (const RecoveryError& e) {
        std::lock_guard lock(mutex_);
        if (stampDue) stampDue_ = true;
        if (!failureLogged_ && log_) log_(std::string("unsaved edits not kept: ") + e.what());
        failureLogged_ = true;
        kept.error = e.what();
    }
    if (!kept.unsaved) kept.file.clear();
    return kept;
}

}  // namespace ray
