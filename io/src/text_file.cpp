// Reading a whole input file without letting a stream exception out: on Linux a folder opens
// as a file and throws on the first read.

#include "text_file.hpp"

#include <fstream>
#include <iterator>
#include <system_error>

namespace collide::io {

std::optional<std::string> read_text_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return std::nullopt;
  try {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) return std::nullopt;
    return text;
  } catch (const std::exception&) {  // std::ios_base::failure from the stream buffer
    return std::nullopt;
  }
}

}  // namespace collide::io
