// StopSignals (viewer/stop_signals.h): sigtimedwait on a thread of its own.
#include "viewer/stop_signals.h"

#include <pthread.h>
#include <signal.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <thread>

namespace ray {

namespace {

std::mutex actionMutex;
std::function<void(int)> action;
std::atomic<bool> ending{false};
std::thread waiter;

sigset_t stopSet() {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGHUP);
    return set;
}

[[noreturn]] void stopProcess(int signal) {
    // A second signal meanwhile ends the process by its default action.
    const sigset_t set = stopSet();
    pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
    {
        // Held while it runs: whoever set it cannot go away meanwhile (beforeExit waits).
        std::lock_guard lock(actionMutex);
        if (action) action(signal);
    }
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    // Not exit(): the server's and the renderer's threads are still running, and static
    // destructors must not run under them.
    std::_Exit(128 + signal);
}

void waitForSignals() {
    const sigset_t set = stopSet();
    const timespec tick{0, 200'000'000};  // how soon the thread sees that it is to end
    while (!ending) {
        const int signal = sigtimedwait(&set, nullptr, &tick);
        if (signal > 0) stopProcess(signal);
    }
}

}  // namespace

StopSignals::StopSignals() {
    const sigset_t set = stopSet();
    pthread_sigmask(SIG_BLOCK, &set, nullptr);
    ending = false;
    waiter = std::thread(waitForSignals);
}

StopSignals::~StopSignals() {
    ending = true;
    waiter.join();
    beforeExit(nullptr);
    const sigset_t set = stopSet();
    pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
}

void StopSignals::beforeExit(std::function<void(int signal)> newAction) {
    std::lock_guard lock(actionMutex);
    action = std::move(newAction);
}

}  // namespace ray
