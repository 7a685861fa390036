// Unsaved edits kept for ray view (host/viewer/recovery.h): a recovery written and read back
// whole, found by its scene, newest first; what is not one refused; the keeper's copy
// written, replaced, set aside and removed as the document says. (tests/viewer/
// test_recovery.py stops and kills real viewers.)
#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "viewer/recovery.h"

namespace {

namespace fs = std::filesystem;
using ray::Recovery;
using ray::RecoveryError;
using ray::RecoveryKeeper;

fs::path scratch(const std::string& name) {
    const fs::path folder = fs::temp_directory_path() / ("ray_recovery_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(folder);
    fs::create_directories(folder);
    return folder;
}

fs::path sceneIn(const fs::path& folder, const std::string& text = "<scenefile></scenefile>\n") {
    const fs::path scene = folder / "scene.xml";
    std::ofstream(scene) << text;
    return scene;
}

unsigned modeOf(const fs::path& path) {
    struct stat facts {};
    REQUIRE(::lstat(path.c_str(), &facts) == 0);
    return facts.st_mode & 0777;
}

// Waits (up to a minute: a loaded machine) until `done` holds.
template <typename Condition>
bool eventually(Condition done) {
    for (int i = 0; i < 6000; ++i) {
        if (done()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return done();
}

std::string contentOf(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST_CASE("a recovery is written private and read back whole, naming its scene, a damaged one is refused",
          "[viewer][recovery]") {
    const fs::path folder = scratch("roundtrip");
    const fs::path scene = sceneIn(folder);
    const fs::path keep = folder / "state" / "ray" / "recovery";
    ray::prepareRecoveryFolder(keep);
    CHECK(modeOf(keep) == 0700);
    const std::string document = "<scenefile>\n  <!-- an edit \xc3\xa9 -->\n</scenefile>\n";
    const fs::path file = keep / "k-1.ray-recovery";
    ray::writeRecovery(file, scene, ray::sceneFileStampOf(scene), document);
    CHECK(modeOf(file) == 0600);

    const Recovery read = ray::readRecovery(file);
    CHECK(read.document == document);
    CHECK(fs::path(read.scene) == fs::canonical(scene));
    CHECK(read.sceneWhenRead == ray::sceneFileStampOf(scene));
    CHECK_FALSE(ray::sceneChangedSince(read, scene));
    std::ofstream(scene, std::ios::app) << "<!-- changed elsewhere -->\n";
    CHECK(ray::sceneChangedSince(read, scene));

    // Cut short, or a byte changed: refused with the reason.
    const std::string whole = contentOf(file);
    std::ofstream(file, std::ios::binary | std::ios::trunc) << whole.substr(0, whole.size() - 3);
    CHECK_THROWS_WITH(ray::readRecovery(file), Catch::Contains("cut short"));
    std::string damaged = whole;
    damaged[damaged.size() - 5] ^= 1;
    std::ofstream(file, std::ios::binary | std::ios::trunc) << damaged;
    CHECK_THROWS_WITH(ray::readRecovery(file), Catch::Contains("does not match its own hash"));
    // A link (even to a good recovery) and a folder are no recovery files.
    std::ofstream(file, std::ios::binary | std::ios::trunc) << whole;
    fs::create_symlink(file, keep / "link.ray-recovery");
    CHECK_THROWS_AS(ray::readRecovery(keep / "link.ray-recovery"), RecoveryError);
    fs::create_directory(keep / "folder.ray-recovery");
    CHECK_THROWS_WITH(ray::readRecovery(keep / "folder.ray-recovery"), Catch::Contains("not a regular file"));
    fs::remove_all(folder);
}

TEST_CASE("the recovery folder is made private, a link in its place is refused", "[viewer][recovery]") {
    const fs::path folder = scratch("folder");
    fs::create_directories(folder / "open");
    fs::permissions(folder / "open", fs::perms(0755));
    ray::prepareRecoveryFolder(folder / "open");
    CHECK(modeOf(folder / "open") == 0700);
    fs::create_directory_symlink(folder / "open", folder / "link");
    CHECK_THROWS_WITH(ray::prepareRecoveryFolder(folder / "link"), Catch::Contains("not a folder"));
    fs::remove_all(folder);
}

TEST_CASE("the keeper writes the document's copy, replaces the one restored, sets edits aside and removes "
          "the copy once saved", "[viewer][recovery]") {
    const fs::path folder = scratch("keeper");
    const fs::path scene = sceneIn(folder);
    const fs::path keep = folder / "recovery";
    std::mutex mutex;
    std::optional<std::string> unsaved;  // what the "viewer" holds
    const auto snapshot = [&]() -> std::optional<std::string> {
        std::lock_guard lock(mutex);
        return unsaved;
    };
    const auto set = [&](std::optional<std::string> text) {
        std::lock_guard lock(mutex);
        unsaved = std::move(text);
    };
    // Another viewer's copy, which this one restored.
    const fs::path restored = keep / "restored.ray-recovery";
    ray::prepareRecoveryFolder(keep);
    ray::writeRecovery(restored, scene, ray::sceneFileStampOf(scene), "<scenefile>restored</scenefile>");

    RecoveryKeeper keeper(keep, scene, snapshot, nullptr);
    const fs::path own = keeper.file();
    CHECK(own.parent_path() == keep);
    CHECK_FALSE(fs::exists(own));  // nothing unsaved, nothing kept

    set("<scenefile>one</scenefile>");
    keeper.replaces(restored);
    keeper.changed();  // a while later
    // The restored copy goes once the keeper's own is there (never a moment without one).
    REQUIRE(eventually([&] { return fs::exists(own) && !fs::exists(restored); }));
    CHECK(ray::readRecovery(own).document == "<scenefile>one</scenefile>");

    // Stopped by a signal: written at once, on the caller's thread.
    set("<scenefile>two</scenefile>");
    const RecoveryKeeper::Kept kept = keeper.keepNow();
    CHECK(kept.unsaved);
    CHECK(kept.file == own);
    CHECK(ray::readRecovery(own).document == "<scenefile>two</scenefile>");

    // The file changed on disk over unsaved edits: they stay in this file; later ones go
    // to another.
    CHECK(keeper.setAside("<scenefile>two</scenefile>") == own);
    set(std::nullopt);
    keeper.changed(true);
    const fs::path next = keeper.file();
    CHECK(next != own);
    REQUIRE(eventually([&] { return !fs::exists(next) && fs::exists(own); }));
    CHECK(ray::readRecovery(own).document == "<scenefile>two</scenefile>");

    set("<scenefile>three</scenefile>");
    keeper.changed();
    REQUIRE(eventually([&] { return fs::exists(next); }));
    const auto found = ray::findRecoveries(keep, scene, nullptr, next);
    REQUIRE(found.size() == 1);
    CHECK(found[0].file == own);

    // Saved: the copy goes (at once), the one set aside stays for the next viewer.
    set(std::nullopt);
    keeper.changed(true);
    REQUIRE(eventually([&] { return !fs::exists(next); }));
    CHECK(fs::exists(own));
    CHECK_FALSE(keeper.keepNow().unsaved);
    keeper.stop();
    fs::remove_all(folder);
}
