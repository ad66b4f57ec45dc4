#pragma once
// What the fuzz targets' contracts (fuzz/*_check.hpp) share: the rule for an error message (it
// names the file and is valid UTF-8), where queries owe finite answers, the scratch files the
// file readers are given, and the libFuzzer entry point's turning of a broken contract into an
// abort.

#include <collide/core/finite_range.hpp>
#include <collide/core/math.hpp>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <unistd.h>

namespace collide::fuzz {

/// "" when `message` (an InvalidInput's) starts with `prefix` (the file's name and its colon, as
/// the reader writes it) and is valid UTF-8; else what is wrong with it.
inline std::string check_message(const std::string& message, const std::string& prefix) {
  if (message.rfind(prefix, 0) != 0) return "message does not name the file: " + message;
  try {
    (void)nlohmann::json(message).dump();  // throws on bytes that are not UTF-8
  } catch (const std::exception&) {
    return "message is not valid UTF-8: " + message;
  }
  return {};
}

/// The bounds `box` (an Aabb or Aabb3) lie within kFiniteQueryRange of the origin, where queries
/// promise finite results.
template <class Box>
bool within_finite_range(const Box& box) {
  return is_finite(box.min) && is_finite(box.max) && max_abs(box.min) <= kFiniteQueryRange &&
         max_abs(box.max) <= kFiniteQueryRange;
}

/// A scratch path of this process in the temporary folder: STEM.PID followed by `extension`, so
/// fuzzing processes running side by side do not share one. Removed, with anything under it,
/// when the process exits normally: libFuzzer's -fork mode starts a process per job, and each
/// left its scratch file behind (thousands in a campaign's tmpfs).
inline std::filesystem::path scratch_path(const std::string& stem, const std::string& extension = "") {
  struct Cleanup {
    std::vector<std::filesystem::path> paths;
    Cleanup() = default;
    Cleanup(const Cleanup&) = delete;
    Cleanup& operator=(const Cleanup&) = delete;
    ~Cleanup() {
      for (const std::filesystem::path& p : paths) {
        std::error_code ignored;
        std::filesystem::remove_all(p, ignored);
      }
    }
  };
  static Cleanup cleanup;
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / (stem + "." + std::to_string(::getpid()) + extension);
  cleanup.paths.push_back(path);
  return path;
}

/// Writes `bytes` to the file `path` (created or truncated); false when it cannot be written.
inline bool write_file(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return static_cast<bool>(out);
}

/// The fuzz input as text.
inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// What LLVMFuzzerTestOneInput returns for the contract's verdict `problem`: 0 when it is "",
/// else an abort after "TARGET: PROBLEM" on stderr (libFuzzer keeps the input as a crash).
inline int report(const char* target, const std::string& problem) {
  if (problem.empty()) return 0;
  std::fprintf(stderr, "%s: %s\n", target, problem.c_str());
  std::abort();
}

}  // namespace collide::fuzz
