// Test hooks: environment variables that only tests set, to make a failure happen at a known
// point (a device that fails or hangs, a rank that stops, a write killed halfway) or to take
// a path this machine would not take by itself (a packet width, a short traversal stack, a
// copied scene). They are read here and nowhere else (readTestHooks), into one struct that
// the code acting on them is given: the OpenCL engine takes one when it is made (a test can
// hand it one without touching the environment), the distributed render reads this
// process's once and passes it on; the atomic file write, below them all, asks testHooks().
// Unset, every hook is off.
#pragma once

#include <optional>
#include <string>

namespace ray {

// A hook aimed at one device of an engine's selection, "k:n": device k (0-based), value n.
struct DeviceHook {
    int device = -1;  // negative: off
    int value = 0;

    // n when `slot` is device k, else nothing.
    std::optional<int> forDevice(int slot) const;
};

struct TestHooks {
    // The atomic file write (core/atomic_file.cpp; tests/fault_injection.sh).
    int writePauseMs = 0;  // RAY_TEST_WRITE_PAUSE_MS: pause halfway, so a test can kill -9 the writer

    // The OpenCL engine's devices (opencl/opencl_engine.h; tests/multi_device.sh, test_engine.cpp).
    DeviceHook failDevice;  // RAY_TEST_FAIL_DEVICE="k:n": fails, as a lost device, once it kept n tiles of a frame
    DeviceHook hangDevice;  // RAY_TEST_HANG_DEVICE="k:n": its launches after the first n never end
    DeviceHook slowBuild;   // RAY_TEST_SLOW_BUILD="k:s": its kernel build takes s seconds longer

    // The kernel a CPU device is built with (opencl/kernel_build.h; tests/cpu_paths.sh,
    // kernel_short_stack.sh, oclgrind.sh).
    std::optional<int> cpuPacketLanes;         // RAY_CPU_PACKETS: 0 (kept as 1: one ray a work-item), 4, 8 or 16
    std::optional<std::string> bvhShortStack;  // RAY_TEST_BVH_SHORT_STACK as set; bvhShortStackEntries reads it
    bool copyScene = false;                    // RAY_TEST_COPY_SCENE: a CPU device gets a copy of the scene's tables

    // A worker rank of mpirun stops itself with SIGSTOP, as a wedged host would
    // (distributed/; tests/mpi.sh). 0: never.
    double stopWhileLoadingSeconds = 0;  // RAY_TEST_STOP_WHILE_LOADING=s: its start-up takes s s more, then it stops
    int stopAfterTiles = 0;              // RAY_TEST_STOP_AFTER_TILES=n: once it has sent n tiles
    double stopAfterSeconds = 0;         // RAY_TEST_STOP_AFTER_SECONDS=s: s s after its message loop began
    // Rank 0 delays the MPI_Abort that ends a job without a silent rank, so that the workers
    // told to wait for it surely do (distributed/mpi_protocol.h awaitAbort).
    double abortAfterSeconds = 0;  // RAY_TEST_ABORT_AFTER_SECONDS

    // The traversal stack's entries the kernel is built with, 0 for its own
    // (RAY_TEST_BVH_SHORT_STACK, 1 to 64: tests make every walk overflow it, cl/traversal/stack.cl
    // BvhStack). Throws std::invalid_argument for another value, at the kernel build, so
    // that only an OpenCL device refuses it.
    int bvhShortStackEntries() const;
};

// Every hook, from the environment: the one place ray reads them.
TestHooks readTestHooks();

// This process's hooks, read on the first call.
const TestHooks& testHooks();

}  // namespace ray
