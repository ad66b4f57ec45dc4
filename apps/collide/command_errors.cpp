// Exit status 2 with a message for everything that can go wrong around a subcommand.

#include "command_errors.hpp"

#include <collide/core/error.hpp>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <system_error>

namespace collide::cli {

int run_guarded(const char* command, const std::string& input, const std::function<int()>& body) noexcept {
  try {
    try {
      return body();
    } catch (const InvalidInput& e) {
      std::fprintf(stderr, "collide %s: %s\n", command, e.what());
    } catch (const std::bad_alloc&) {
      std::fprintf(stderr, "collide %s: %s: out of memory\n", command, input.c_str());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "collide %s: %s: %s\n", command, input.c_str(), e.what());
    }
  } catch (...) {  // not even the message could be made, or not a std::exception
    std::fprintf(stderr, "collide %s: failed (no message could be made)\n", command);
  }
  return 2;
}

void require_input_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);  // follows links; never opens the file
  const char* why = nullptr;
  switch (st.type()) {
    case fs::file_type::regular: break;
    case fs::file_type::not_found: why = "no such file"; break;
    case fs::file_type::directory: why = "a directory"; break;
    case fs::file_type::fifo: why = "a FIFO: give a regular file"; break;
    case fs::file_type::character:
    case fs::file_type::block: why = "a device: give a regular file"; break;
    case fs::file_type::socket: why = "a socket: give a regular file"; break;
    default: why = ec ? "its status cannot be read" : "not a regular file"; break;
  }
  if (why == nullptr && fs::file_size(path, ec) == 0 && !ec) why = "an empty file";
  if (why != nullptr) throw InvalidInput(path + ": cannot be read (" + why + ")");
}

void require_output_folder(const std::string& option, const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::path(path).parent_path();
  std::error_code ec;
  if (!folder.empty() && !fs::is_directory(folder, ec)) {
    throw InvalidInput(option + " " + path + ": cannot be written (no folder '" + folder.generic_string() + "')");
  }
}

}  // namespace collide::cli
