#pragma once
// Running the real `collide` binary from tests: its exit status and everything it printed.

#include <array>
#include <cstdio>
#include <fstream>
#include <string>

#include <sys/wait.h>

// Memory limits (ulimit -v) and AddressSanitizer's shadow memory do not mix: such tests skip.
#if defined(__SANITIZE_ADDRESS__)
#define COLLIDE_TEST_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define COLLIDE_TEST_UNDER_ASAN 1
#endif
#endif

namespace collide::test {

/// What one run of the tool did.
struct CommandRun {
  int status = -1;      ///< as pclose returns it: 0 on success
  std::string output;   ///< stdout and stderr together
};

/// Runs `collide ARGS` through the shell (COLLIDE_CLI_PATH is the built binary).
inline CommandRun run_cli(const std::string& args) {
  const std::string cmd = std::string(COLLIDE_CLI_PATH) + " " + args + " 2>&1";
  CommandRun r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), static_cast<int>(buf.size()), pipe) != nullptr) r.output += buf.data();
  r.status = pclose(pipe);
  return r;
}

/// Runs `sh -c SCRIPT` (stdout and stderr together); the script finds the built tool in $COLLIDE.
inline CommandRun run_shell(const std::string& script) {
  const std::string cmd = "COLLIDE='" + std::string(COLLIDE_CLI_PATH) + "'; " + script + " 2>&1";
  CommandRun r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), static_cast<int>(buf.size()), pipe) != nullptr) r.output += buf.data();
  r.status = pclose(pipe);
  return r;
}

/// The exit status of a run that exited, -1 for one that was killed (an abort).
inline int exit_code(const CommandRun& r) { return WIFEXITED(r.status) ? WEXITSTATUS(r.status) : -1; }

/// True when `path` starts with the 8-byte PNG signature.
inline bool has_png_signature(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::array<unsigned char, 8> signature{};
  file.read(reinterpret_cast<char*>(signature.data()), signature.size());
  const std::array<unsigned char, 8> expected = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return file.good() && signature == expected;
}

}  // namespace collide::test
