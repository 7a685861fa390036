// Atomic file writes (core/atomic_file) and the clear messages of issue 16. The faults that
// need root (a full tmpfs, other users, kill -9) are in tests/fault_injection.sh.
#include <catch2/catch.hpp>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include "core/atomic_file.h"
#include "core/input_file.h"
#include "image/image.h"
#include "scene/mesh.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

fs::path freshFolder(const std::string& name) {
    fs::path dir = ray::test::outputDir() / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string contents(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

size_t entriesIn(const fs::path& dir) {
    size_t n = 0;
    for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++n;
    return n;
}

}  // namespace

TEST_CASE("writeFileAtomically writes, replaces and leaves nothing else in the folder", "[atomic_file]") {
    fs::path dir = freshFolder("atomic_replace");
    ray::writeFileAtomically(dir / "a.json", "first");
    CHECK(contents(dir / "a.json") == "first");
    ray::writeFileAtomically(dir / "a.json", "second, longer");
    CHECK(contents(dir / "a.json") == "second, longer");
    CHECK(entriesIn(dir) == 1);
}

TEST_CASE("a write into a missing folder names the path and the system's reason", "[atomic_file]") {
    fs::path target = freshFolder("atomic_missing") / "no" / "such" / "out.json";
    try {
        ray::writeFileAtomically(target, "x");
        FAIL("no error");
    } catch (const ray::FileWriteError& e) {
        CHECK_THAT(e.what(), Contains(target.string()));
        CHECK_THAT(e.what(), Contains("No such file or directory"));
    }
}

TEST_CASE("an encoder that fails leaves the old file and no temporary file", "[atomic_file]") {
    fs::path dir = freshFolder("atomic_encoder_fails");
    ray::writeFileAtomically(dir / "img.png", "old");
    fs::path seen;
    CHECK_THROWS_WITH(ray::writeFileAtomicallyVia(dir / "img.png",
                                                  [&](const fs::path& tmp) {
                                                      seen = tmp;
                                                      std::ofstream(tmp) << "half";
                                                      throw std::runtime_error("encoder failed");
                                                  }),
                      "encoder failed");
    CHECK(seen.parent_path() == dir);  // beside the target: the rename stays on one file system
    CHECK(seen.extension() == ".png");  // encoders choose the format by extension
    CHECK(contents(dir / "img.png") == "old");
    CHECK(entriesIn(dir) == 1);
}

TEST_CASE("writeImage goes through the atomic writer for memory and path encoders", "[atomic_file]") {
    fs::path dir = freshFolder("atomic_images");
    ray::Image image(4, 3);
    image.set(1, 1, {1, 0.5, 0.25});
    for (const char* name : {"a.png", "a.ppm", "a.exr", "a.hdr", "a.tif", "a.jpg"}) {
        ray::writeImage(image, dir / name);
        ray::Image back = ray::readImage(dir / name);
        CHECK(back.width == 4);
        CHECK(back.height == 3);
    }
    CHECK(entriesIn(dir) == 6);
    CHECK_THROWS_WITH(ray::writeImage(image, dir / "missing" / "a.png"), Contains("No such file or directory"));
}

TEST_CASE("a folder given as the scene file says so", "[atomic_file][loader]") {
    fs::path dir = freshFolder("scene_is_folder");
    CHECK_THROWS_WITH(ray::loadScene(dir), Contains("is a folder, not a scene file"));
}

TEST_CASE("an OBJ parse error names the file and line on every line of the message", "[atomic_file][loader]") {
    fs::path obj = freshFolder("obj_error") / "bad.obj";
    std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nf 0 0 0\n";
    try {
        ray::loadObjMesh(obj);
        FAIL("no error");
    } catch (const ray::InputError& e) {
        std::istringstream lines(e.what());
        std::string line;
        std::getline(lines, line);
        CHECK_THAT(line, Contains(obj.string() + ":3: error:"));
        while (std::getline(lines, line)) CHECK_THAT(line, Contains(obj.string()));
    }
}

TEST_CASE("a texture that is a FIFO is refused without opening it", "[atomic_file]") {
    fs::path fifo = freshFolder("fifo_texture") / "t.png";
    REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
    CHECK_THROWS_WITH(ray::readImage(fifo), Contains("not a regular file (a FIFO)"));
    CHECK_THROWS_WITH(ray::readImage("/dev/zero"), Contains("not a regular file"));
}

// ---------------------------------------------------------------------------------------
// The one writer (issue 49): what is at the target decides how it is written. In a scratch
// folder, never in /dev.

namespace {

mode_t modeOf(const fs::path& file) {
    struct stat status {};
    REQUIRE(::stat(file.c_str(), &status) == 0);
    return status.st_mode;
}

std::vector<std::string> warningsOf(const std::function<void(const ray::WriteOptions&)>& write) {
    std::vector<std::string> warnings;
    ray::WriteOptions options;
    options.warn = [&](const std::string& w) { warnings.push_back(w); };
    write(options);
    return warnings;
}

}  // namespace

TEST_CASE("a FIFO is written into, its reader gets the bytes, and it stays a FIFO", "[atomic_file][writer]") {
    const fs::path fifo = freshFolder("writer_fifo") / "stats.json";
    REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
    std::string received;
    std::thread reader([&] { received = contents(fifo); });  // blocks in open until the writer comes
    ray::writeFileAtomically(fifo, "{\"rays\": 42}\n");
    reader.join();
    CHECK(received == "{\"rays\": 42}\n");
    CHECK(fs::is_fifo(fs::symlink_status(fifo)));
    CHECK(entriesIn(fifo.parent_path()) == 1);
}

TEST_CASE("an encoder's file reaches a FIFO whole", "[atomic_file][writer]") {
    const fs::path fifo = freshFolder("writer_fifo_via") / "out.png";
    REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
    std::string received;
    std::thread reader([&] { received = contents(fifo); });
    ray::writeFileAtomicallyVia(fifo, [](const fs::path& tmp) { std::ofstream(tmp) << "encoded bytes"; });
    reader.join();
    CHECK(received == "encoded bytes");
    CHECK(fs::is_fifo(fs::symlink_status(fifo)));
}

TEST_CASE("a character device is written into, not replaced by a file", "[atomic_file][writer]") {
    if (::geteuid() != 0) {
        WARN("skipped: making a character device (mknod) needs root");
        return;
    }
    const fs::path null = freshFolder("writer_chardev") / "null";
    if (::mknod(null.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) {  // what /dev/null is
        WARN("skipped: this container refuses mknod (" << std::strerror(errno) << ")");
        return;
    }
    ray::writeFileAtomically(null, "into the device");
    CHECK(S_ISCHR(modeOf(null)));
    CHECK(fs::is_character_file(fs::symlink_status(null)));
    CHECK(entriesIn(null.parent_path()) == 1);
}

TEST_CASE("a symbolic link stays a link and its target gets the bytes", "[atomic_file][writer]") {
    const fs::path dir = freshFolder("writer_link");
    fs::create_directories(dir / "real");
    fs::create_directories(dir / "links");
    ray::writeFileAtomically(dir / "real" / "scene.xml", "old");
    fs::create_symlink("../real/scene.xml", dir / "links" / "scene.xml");  // relative, from another folder
    fs::create_symlink("scene.xml", dir / "links" / "again.xml");         // a link to a link
    ray::writeFileAtomically(dir / "links" / "again.xml", "new");
    CHECK(fs::is_symlink(dir / "links" / "scene.xml"));
    CHECK(fs::is_symlink(dir / "links" / "again.xml"));
    CHECK(contents(dir / "real" / "scene.xml") == "new");
    CHECK(entriesIn(dir / "links") == 2);  // no temporary file left beside the links
    CHECK(entriesIn(dir / "real") == 1);

    // A dangling link: its target is created, as the shell's > would.
    fs::create_symlink("../real/new.json", dir / "links" / "dangling.json");
    ray::writeFileAtomically(dir / "links" / "dangling.json", "made");
    CHECK(fs::is_symlink(dir / "links" / "dangling.json"));
    CHECK(contents(dir / "real" / "new.json") == "made");
}

TEST_CASE("a replaced file keeps its mode, a read-only one is refused unless told", "[atomic_file][writer]") {
    const fs::path dir = freshFolder("writer_modes");
    const fs::path secret = dir / "secret.xml";
    ray::writeFileAtomically(secret, "one");
    fs::permissions(secret, fs::perms::owner_read | fs::perms::owner_write);
    ray::writeFileAtomically(secret, "two");
    CHECK((modeOf(secret) & 07777) == 0600);
    CHECK(contents(secret) == "two");

    const fs::path locked = dir / "locked.xml";
    ray::writeFileAtomically(locked, "kept");
    fs::permissions(locked, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);  // 444
    CHECK_THROWS_AS(ray::writeFileAtomically(locked, "lost"), ray::OutputRefused);
    CHECK_THROWS_WITH(ray::writeFileAtomically(locked, "lost"),
                      Contains(locked.string()) && Contains("read-only") && Contains("--replace-read-only"));
    CHECK_THROWS_AS(ray::checkCanWrite(locked), ray::OutputRefused);
    CHECK(contents(locked) == "kept");
    CHECK((modeOf(locked) & 07777) == 0444);

    ray::WriteOptions replace;
    replace.replaceReadOnly = true;
    ray::checkCanWrite(locked, replace);
    ray::writeFileAtomically(locked, "replaced", replace);
    CHECK(contents(locked) == "replaced");
    CHECK((modeOf(locked) & 07777) == 0444);  // still read-only: asked to replace, not to unlock
    CHECK(entriesIn(dir) == 2);
}

TEST_CASE("a file with other hard links is replaced, and the warning names it", "[atomic_file][writer]") {
    const fs::path dir = freshFolder("writer_hard_link");
    ray::writeFileAtomically(dir / "a.xml", "old");
    fs::create_hard_link(dir / "a.xml", dir / "b.xml");
    const std::vector<std::string> warnings =
        warningsOf([&](const ray::WriteOptions& o) { ray::writeFileAtomically(dir / "a.xml", "new", o); });
    REQUIRE(warnings.size() == 1);
    CHECK_THAT(warnings[0], Contains((dir / "a.xml").string()) && Contains("2 hard links") &&
                                Contains("1 other name keeps the old contents"));
    CHECK(contents(dir / "a.xml") == "new");
    CHECK(contents(dir / "b.xml") == "old");
}

TEST_CASE("a folder is refused with a sentence, before and at the write", "[atomic_file][writer]") {
    const fs::path dir = freshFolder("writer_folder");
    fs::create_directories(dir / "out.png");
    CHECK_THROWS_WITH(ray::checkCanWrite(dir / "out.png"), Contains("is a folder") && Contains("name a file in it"));
    CHECK_THROWS_AS(ray::writeFileAtomically(dir / "out.png", "x"), ray::OutputRefused);
    CHECK(fs::is_directory(dir / "out.png"));
}

TEST_CASE("a socket is refused with a sentence, and stays a socket", "[atomic_file][writer]") {
    const fs::path socketPath = freshFolder("writer_socket") / "s.json";
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    REQUIRE(fd >= 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    const std::string path = socketPath.string();
    REQUIRE(path.size() < sizeof address.sun_path);
    std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
    REQUIRE(::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0);
    CHECK_THROWS_WITH(ray::writeFileAtomically(socketPath, "x"), Contains("is a socket, not a file ray can write"));
    CHECK_THROWS_AS(ray::checkCanWrite(socketPath), ray::OutputRefused);
    CHECK(fs::is_socket(fs::symlink_status(socketPath)));
    ::close(fd);
}

TEST_CASE("the process's own descriptors are written through, not reopened", "[atomic_file][writer]") {
    int pipeEnds[2];
    REQUIRE(::pipe(pipeEnds) == 0);
    ray::writeFileAtomically("/proc/self/fd/" + std::to_string(pipeEnds[1]), "through the pipe");
    ray::writeFileAtomically("/dev/fd/" + std::to_string(pipeEnds[1]), "!");
    ::close(pipeEnds[1]);
    char buffer[64] = {};
    const ssize_t n = ::read(pipeEnds[0], buffer, sizeof buffer);
    ::close(pipeEnds[0]);
    CHECK(std::string(buffer, size_t(std::max<ssize_t>(n, 0))) == "through the pipe!");
    CHECK_THROWS_WITH(ray::writeFileAtomically("/dev/fd/987", "x"), Contains("descriptor 987"));
}

TEST_CASE("an output that is the input, also through a link, is refused", "[atomic_file][writer]") {
    const fs::path dir = freshFolder("writer_input");
    ray::writeFileAtomically(dir / "s.xml", "<scenefile/>");
    fs::create_symlink("s.xml", dir / "link.json");
    CHECK_THROWS_WITH(ray::refuseWritingOverInput(dir / "s.xml", "--stats-json", dir / "s.xml", "the scene"),
                      Contains("is the scene") && Contains("--stats-json"));
    CHECK_THROWS_AS(ray::refuseWritingOverInput(dir / "link.json", "--json", dir / "s.xml", "the scene"),
                    ray::OutputRefused);
    ray::refuseWritingOverInput(dir / "other.json", "--json", dir / "s.xml", "the scene");  // not there: fine
}

// ---------------------------------------------------------------------------------------
// Files ray reads (core/input_file.h): regular files of a size their kind justifies.

TEST_CASE("a FIFO, a device or an oversized file named as an input is refused at once", "[atomic_file][reader]") {
    const fs::path dir = freshFolder("input_files");
    const fs::path fifo = dir / "mesh.obj";
    REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
    const ray::InputLimit limit{"a test file", 16, "sixteen bytes"};
    CHECK_THROWS_WITH(ray::readInputFile(fifo, limit), Contains("is not a regular file (a FIFO)"));
    CHECK_THROWS_WITH(ray::readInputFile("/dev/zero", limit), Contains("a character device"));
    std::ofstream(dir / "big.txt") << "seventeen bytes!!";
    CHECK_THROWS_WITH(ray::readInputFile(dir / "big.txt", limit), Contains("more than a test file can need"));
    std::ofstream(dir / "small.txt") << "fits";
    CHECK(ray::readInputFile(dir / "small.txt", limit) == "fits");
}

TEST_CASE("an OBJ that is a FIFO or /dev/zero is refused, never read", "[atomic_file][reader][mesh]") {
    const fs::path dir = freshFolder("obj_fifo");
    const fs::path fifo = dir / "mesh.obj";
    REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
    CHECK_THROWS_WITH(ray::loadObjMesh(fifo), Contains("mesh.obj: error:") && Contains("a FIFO"));
    fs::create_symlink("/dev/zero", dir / "zero.obj");
    CHECK_THROWS_WITH(ray::loadObjMesh(dir / "zero.obj"), Contains("a character device"));
}

TEST_CASE("an OBJ's mtllib is read from its folder only, and only a regular file", "[atomic_file][reader][mesh]") {
    const fs::path dir = freshFolder("obj_mtllib");
    fs::create_directories(dir / "meshes");
    const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";
    auto objWith = [&](const std::string& name, const std::string& mtllib) {
        std::ofstream(dir / "meshes" / name) << "mtllib " << mtllib << "\n" << triangle;
        return dir / "meshes" / name;
    };
    std::ofstream(dir / "meshes" / "good.mtl") << "newmtl red\nKd 1 0 0\n";
    CHECK(ray::loadObjMesh(objWith("good.obj", "good.mtl")).triangles.size() == 1);
    CHECK(ray::loadObjMesh(objWith("missing.obj", "missing.mtl")).triangles.size() == 1);  // as before

    REQUIRE(mkfifo((dir / "meshes" / "fifo.mtl").c_str(), 0600) == 0);
    CHECK_THROWS_WITH(ray::loadObjMesh(objWith("fifo.obj", "fifo.mtl")),
                      Contains("fifo.obj: error: mtllib 'fifo.mtl'") && Contains("a FIFO"));
    fs::create_symlink("/dev/zero", dir / "meshes" / "zero.mtl");
    CHECK_THROWS_WITH(ray::loadObjMesh(objWith("zero.obj", "zero.mtl")), Contains("outside the OBJ's folder"));
    std::ofstream(dir / "outside.mtl") << "newmtl red\n";
    CHECK_THROWS_WITH(ray::loadObjMesh(objWith("up.obj", "../outside.mtl")),
                      Contains("up.obj: error: mtllib '../outside.mtl' is outside the OBJ's folder"));
    CHECK_THROWS_WITH(ray::loadObjMesh(objWith("abs.obj", "/etc/passwd")), Contains("outside the OBJ's folder"));
}

TEST_CASE("a large file that is no image is refused by its first bytes, not decoded", "[atomic_file][reader]") {
    const fs::path file = freshFolder("texture_not_image") / "big.png";
    {
        std::ofstream out(file);
        out << "this is a text file, not an image\n";
    }
    fs::resize_file(file, uint64_t(128) << 20);  // 128 MiB, sparse
    CHECK_THROWS_WITH(ray::readImage(file), Contains("big.png") && Contains("no image format"));
    fs::resize_file(file, (uint64_t(1) << 30));  // past what a texture can need
    CHECK_THROWS_WITH(ray::readImage(file), Contains("more than an image can need"));
}
