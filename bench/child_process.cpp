#include "child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <deque>
#include <fstream>
#include <thread>

extern char** environ;

namespace bench {

namespace {

using Clock = std::chrono::steady_clock;

// How often a running child is checked. Short enough that wall times are good to a few
// milliseconds, long enough to cost nothing next to a render.
constexpr auto kPollInterval = std::chrono::milliseconds(2);

bool overrides(const std::string& entry, const std::vector<std::pair<std::string, std::string>>& environment) {
    for (const auto& [name, value] : environment)
        if (entry.compare(0, name.size() + 1, name + "=") == 0) return true;
    return false;
}

// This process's environment with the command's variables set in it.
std::vector<std::string> childEnvironment(const ChildCommand& command) {
    std::vector<std::string> entries;
    for (char** e = environ; *e; ++e)
        if (!overrides(*e, command.environment)) entries.emplace_back(*e);
    for (const auto& [name, value] : command.environment) entries.push_back(name + "=" + value);
    return entries;
}

// posix_spawn wants NULL-terminated arrays of mutable C strings.
std::vector<char*> cStringArray(std::vector<std::string>& strings) {
    std::vector<char*> pointers;
    for (std::string& s : strings) pointers.push_back(s.data());
    pointers.push_back(nullptr);
    return pointers;
}

// The child's pid, or -errno when it could not be started.
pid_t spawnChild(const ChildCommand& command) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    const std::string log = command.log.empty() ? "/dev/null" : command.log.string();
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);

    std::vector<std::string> args = command.argv;
    std::vector<std::string> env = childEnvironment(command);
    std::vector<char*> argPointers = cStringArray(args);
    std::vector<char*> envPointers = cStringArray(env);
    pid_t pid = -1;
    int error = posix_spawn(&pid, argPointers[0], &actions, nullptr, argPointers.data(), envPointers.data());
    posix_spawn_file_actions_destroy(&actions);
    return error == 0 ? pid : -error;
}

// Reaps the child, killing it once the deadline passes. Polls rather than blocking so that
// the time limit needs neither signals nor a second thread.
void waitWithDeadline(pid_t pid, double timeoutSeconds, Clock::time_point start, ChildOutcome& outcome) {
    int status = 0;
    rusage usage{};
    for (;;) {
        pid_t done = wait4(pid, &status, WNOHANG, &usage);
        if (done == pid) break;
        if (done < 0 && errno != EINTR) return;
        if (timeoutSeconds > 0 && Clock::now() - start > std::chrono::duration<double>(timeoutSeconds)) {
            kill(pid, SIGKILL);
            while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
            }
            outcome.timedOut = true;
            break;
        }
        std::this_thread::sleep_for(kPollInterval);
    }
    outcome.wallSeconds = std::chrono::duration<double>(Clock::now() - start).count();
    outcome.peakMiB = double(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
    if (WIFEXITED(status)) outcome.exitCode = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) outcome.signal = WTERMSIG(status);
}

}  // namespace

std::string ChildOutcome::describe() const {
    if (!started) return std::string("could not start: ") + std::strerror(spawnError);
    if (timedOut) return "timeout";
    if (signal != 0) return "signal " + std::to_string(signal);
    if (exitCode != 0) return "exit " + std::to_string(exitCode);
    return "ok";
}

ChildOutcome runChild(const ChildCommand& command) {
    ChildOutcome outcome;
    auto start = Clock::now();
    pid_t pid = spawnChild(command);
    if (pid < 0) {
        outcome.spawnError = int(-pid);
        return outcome;
    }
    outcome.started = true;
    waitWithDeadline(pid, command.timeoutSeconds, start, outcome);
    return outcome;
}

std::string tailOf(const std::filesystem::path& file, int maxLines) {
    std::ifstream in(file);
    std::deque<std::string> lines;
    for (std::string line; std::getline(in, line);) {
        lines.push_back(line);
        if (int(lines.size()) > maxLines) lines.pop_front();
    }
    std::string text;
    for (const std::string& line : lines) text += "    " + line + "\n";
    return text;
}

}  // namespace bench
