// Running the `ray` binary as a child process and measuring it from outside: wall time,
// peak resident memory (wait4's ru_maxrss), exit status, and a time limit.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace bench {

struct ChildCommand {
    std::vector<std::string> argv;  // argv[0] is the program's path
    // Variables set (or replaced) in the child's copy of this process's environment.
    std::vector<std::pair<std::string, std::string>> environment;
    std::filesystem::path log;    // receives the child's stdout and stderr
    double timeoutSeconds = 0;    // 0: no limit; else SIGKILL once it is exceeded
};

struct ChildOutcome {
    bool started = false;
    bool timedOut = false;
    int exitCode = -1;      // -1 when it did not exit normally
    int signal = 0;         // the signal that ended it, 0 when none
    int spawnError = 0;     // errno from posix_spawn when it did not start
    double wallSeconds = 0;
    double peakMiB = 0;     // the child's peak resident set (and that of any children it waited for)

    bool succeeded() const { return started && !timedOut && exitCode == 0; }
    std::string describe() const;  // "ok", "timeout", "exit 3", "signal 9", "could not start"
};

ChildOutcome runChild(const ChildCommand& command);

// The last `maxLines` lines of a text file, for reporting why a run failed.
std::string tailOf(const std::filesystem::path& file, int maxLines);

}  // namespace bench
