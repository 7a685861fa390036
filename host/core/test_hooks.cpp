#include "core/test_hooks.h"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace ray {

namespace {

// The variable's value; empty when it is unset.
std::string variable(const char* name) {
    const char* value = std::getenv(name);
    return value ? value : "";
}

// "k:n" with n >= 0; anything else leaves the hook off.
DeviceHook deviceHook(const char* name) {
    const std::string text = variable(name);
    DeviceHook hook;
    if (std::sscanf(text.c_str(), "%d:%d", &hook.device, &hook.value) != 2 || hook.value < 0) return {};
    return hook;
}

// RAY_CPU_PACKETS: "0" keeps a CPU device on one ray a work-item; "4", "8" or "16" sets the
// width; anything else leaves the device's own.
std::optional<int> packetLanes(const std::string& text) {
    if (text == "0") return 1;
    if (text == "4" || text == "8" || text == "16") return std::stoi(text);
    return std::nullopt;
}

}  // namespace

std::optional<int> DeviceHook::forDevice(int slot) const {
    if (device < 0 || slot != device) return std::nullopt;
    return value;
}

int TestHooks::bvhShortStackEntries() const {
    if (!bvhShortStack) return 0;
    const char* text = bvhShortStack->c_str();
    char* end = nullptr;
    const long entries = std::strtol(text, &end, 10);
    if (end == text || *end != '\0' || entries < 1 || entries > 64)
        throw std::invalid_argument("RAY_TEST_BVH_SHORT_STACK must be a number from 1 to 64, not '" + *bvhShortStack +
                                    "'");
    return int(entries);
}

TestHooks readTestHooks() {
    TestHooks hooks;
    hooks.writePauseMs = std::atoi(variable("RAY_TEST_WRITE_PAUSE_MS").c_str());
    hooks.failDevice = deviceHook("RAY_TEST_FAIL_DEVICE");
    hooks.hangDevice = deviceHook("RAY_TEST_HANG_DEVICE");
    hooks.slowBuild = deviceHook("RAY_TEST_SLOW_BUILD");
    hooks.cpuPacketLanes = packetLanes(variable("RAY_CPU_PACKETS"));
    if (const char* entries = std::getenv("RAY_TEST_BVH_SHORT_STACK")) hooks.bvhShortStack = entries;
    hooks.copyScene = !variable("RAY_TEST_COPY_SCENE").empty();
    hooks.stopWhileLoadingSeconds = std::atof(variable("RAY_TEST_STOP_WHILE_LOADING").c_str());
    hooks.stopAfterTiles = std::atoi(variable("RAY_TEST_STOP_AFTER_TILES").c_str());
    hooks.stopAfterSeconds = std::atof(variable("RAY_TEST_STOP_AFTER_SECONDS").c_str());
    hooks.abortAfterSeconds = std::atof(variable("RAY_TEST_ABORT_AFTER_SECONDS").c_str());
    return hooks;
}

const TestHooks& testHooks() {
    static const TestHooks hooks = readTestHooks();
    return hooks;
}

}  // namespace ray
