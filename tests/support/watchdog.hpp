#pragma once
// Running a piece of a test that might never return (a loop that does not end on some input) in
// a child process with a watchdog: the parent waits up to a time limit and then kills the child,
// so a hang fails the test instead of stopping the whole suite. The time limit only guards
// against the hang; it is far above the work's duration and asserts nothing about speed.

#include <gtest/gtest.h>

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <string>

namespace collide::test {

/// How the watched work ended.
struct WatchedRun {
  bool finished = false;  ///< the child exited by itself (no hang, no crash)
  std::string report;     ///< everything the work wrote with `say`, in order
};

/// Runs `work(say)` in a forked child; `say(text)` sends text to the parent as it goes (progress
/// lines, failure descriptions). Waits at most `limit_seconds` for the child to finish, then kills
/// it (SIGKILL). `finished` is false when the child was killed or died of a signal.
inline WatchedRun run_with_watchdog(int limit_seconds,
                                    const std::function<void(const std::function<void(const std::string&)>&)>& work) {
  WatchedRun run;
  int fds[2];
  if (pipe(fds) != 0) {
    ADD_FAILURE() << "pipe failed";
    return run;
  }
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) {
    ADD_FAILURE() << "fork failed";
    return run;
  }
  if (pid == 0) {
    close(fds[0]);
    const auto say = [&](const std::string& text) {
      std::size_t done = 0;
      while (done < text.size()) {
        const ssize_t n = write(fds[1], text.data() + done, text.size() - done);
        if (n <= 0) break;
        done += static_cast<std::size_t>(n);
      }
    };
    work(say);
    close(fds[1]);
    _exit(0);
  }
  close(fds[1]);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(limit_seconds);
  char buf[4096];
  bool killed = false;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      kill(pid, SIGKILL);
      killed = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = poll(&p, 1, static_cast<int>(left.count()));
    if (ready < 0) continue;
    if (ready == 0) continue;  // the deadline is checked above
    const ssize_t n = read(fds[0], buf, sizeof buf);
    if (n <= 0) break;  // the child closed its end: done (or crashed)
    run.report.append(buf, static_cast<std::size_t>(n));
  }
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  run.finished = !killed && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (killed) run.report += "\n[killed by the watchdog after " + std::to_string(limit_seconds) + " s: a hang]";
  return run;
}

}  // namespace collide::test
