// The test hooks (host/core/test_hooks.h) as read from the environment: each variable's
// accepted forms, and the forms that leave a hook off, as the scripts that set them expect.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/test_hooks.h"

namespace {

const std::vector<std::string> kHookVariables{
    "RAY_TEST_WRITE_PAUSE_MS",     "RAY_TEST_FAIL_DEVICE",        "RAY_TEST_HANG_DEVICE",
    "RAY_TEST_SLOW_BUILD",         "RAY_CPU_PACKETS",             "RAY_TEST_BVH_SHORT_STACK",
    "RAY_TEST_COPY_SCENE",         "RAY_TEST_STOP_WHILE_LOADING", "RAY_TEST_STOP_AFTER_TILES",
    "RAY_TEST_STOP_AFTER_SECONDS", "RAY_TEST_ABORT_AFTER_SECONDS"};

// The hooks read with `variable` set to `value` and every other hook unset.
ray::TestHooks hooksWith(const std::string& variable, const std::string& value) {
    for (const std::string& v : kHookVariables) ::unsetenv(v.c_str());
    ::setenv(variable.c_str(), value.c_str(), 1);
    ray::TestHooks hooks = ray::readTestHooks();
    ::unsetenv(variable.c_str());
    return hooks;
}

}  // namespace

TEST_CASE("Unset, every test hook is off", "[test_hooks]") {
    for (const std::string& v : kHookVariables) ::unsetenv(v.c_str());
    const ray::TestHooks hooks = ray::readTestHooks();
    CHECK(hooks.writePauseMs == 0);
    for (int slot : {-1, 0, 1}) {
        CHECK_FALSE(hooks.failDevice.forDevice(slot));
        CHECK_FALSE(hooks.hangDevice.forDevice(slot));
        CHECK_FALSE(hooks.slowBuild.forDevice(slot));
    }
    CHECK_FALSE(hooks.cpuPacketLanes);
    CHECK(hooks.bvhShortStackEntries() == 0);
    CHECK_FALSE(hooks.copyScene);
    CHECK(hooks.stopWhileLoadingSeconds == 0);
    CHECK(hooks.stopAfterTiles == 0);
    CHECK(hooks.stopAfterSeconds == 0);
    CHECK(hooks.abortAfterSeconds == 0);
}

TEST_CASE("A device hook k:n aims at device k alone, and other forms leave it off", "[test_hooks]") {
    const ray::TestHooks hooks = hooksWith("RAY_TEST_FAIL_DEVICE", "1:2");
    CHECK(hooks.failDevice.forDevice(1) == 2);
    CHECK_FALSE(hooks.failDevice.forDevice(0));
    CHECK(hooksWith("RAY_TEST_HANG_DEVICE", "0:0").hangDevice.forDevice(0) == 0);
    CHECK(hooksWith("RAY_TEST_SLOW_BUILD", "0:30").slowBuild.forDevice(0) == 30);
    for (const char* off : {"", "1", "1:-2", "x:2"}) {
        INFO(off);
        const ray::DeviceHook hook = hooksWith("RAY_TEST_FAIL_DEVICE", off).failDevice;
        for (int slot : {-1, 0, 1}) CHECK_FALSE(hook.forDevice(slot));
    }
}

TEST_CASE("RAY_CPU_PACKETS takes 0 (one ray) and the widths 4, 8 and 16", "[test_hooks]") {
    CHECK(hooksWith("RAY_CPU_PACKETS", "0").cpuPacketLanes == 1);
    CHECK(hooksWith("RAY_CPU_PACKETS", "8").cpuPacketLanes == 8);
    CHECK(hooksWith("RAY_CPU_PACKETS", "16").cpuPacketLanes == 16);
    CHECK_FALSE(hooksWith("RAY_CPU_PACKETS", "2").cpuPacketLanes);
    CHECK_FALSE(hooksWith("RAY_CPU_PACKETS", "").cpuPacketLanes);
}

TEST_CASE("RAY_TEST_BVH_SHORT_STACK is refused at the kernel build unless 1 to 64", "[test_hooks]") {
    CHECK(hooksWith("RAY_TEST_BVH_SHORT_STACK", "1").bvhShortStackEntries() == 1);
    CHECK(hooksWith("RAY_TEST_BVH_SHORT_STACK", "64").bvhShortStackEntries() == 64);
    for (const char* refused : {"", "0", "65", "4x"}) {
        INFO(refused);
        const ray::TestHooks hooks = hooksWith("RAY_TEST_BVH_SHORT_STACK", refused);  // read without complaint
        CHECK_THROWS_AS(hooks.bvhShortStackEntries(), std::invalid_argument);
    }
}

TEST_CASE("The other hooks take their numbers, and a set RAY_TEST_COPY_SCENE is on", "[test_hooks]") {
    CHECK(hooksWith("RAY_TEST_WRITE_PAUSE_MS", "20000").writePauseMs == 20000);
    CHECK(hooksWith("RAY_TEST_COPY_SCENE", "1").copyScene);
    CHECK_FALSE(hooksWith("RAY_TEST_COPY_SCENE", "").copyScene);
    CHECK(hooksWith("RAY_TEST_STOP_WHILE_LOADING", "3").stopWhileLoadingSeconds == 3);
    CHECK(hooksWith("RAY_TEST_STOP_AFTER_TILES", "20").stopAfterTiles == 20);
    CHECK(hooksWith("RAY_TEST_STOP_AFTER_SECONDS", "2").stopAfterSeconds == 2);
    CHECK(hooksWith("RAY_TEST_ABORT_AFTER_SECONDS", "1.5").abortAfterSeconds == 1.5);
}
