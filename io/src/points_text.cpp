// Points as text, one per line ("x y" or "x y z"): every line checked, the file and line of
// anything wrong named.
#include <collide/io/points_text.hpp>

#include "text_file.hpp"

#include <collide/core/error.hpp>

#include <string>

namespace collide::io {
namespace {

/// The first character of a comment line (after any blanks).
constexpr char kCommentMark = '#';

/// "x y" or "x y z": how a line of `D` numbers reads, for messages.
template <int D>
const char* coordinates_named() {
  return D == 2 ? "x y" : "x y z";
}

}  // namespace

template <int D>
std::vector<VecN<D>> parse_points(std::string_view text, const std::filesystem::path& name) {
  static_assert(D == 2 || D == 3, "points are 2D or 3D");
  const std::string file = name.string();
  std::vector<VecN<D>> points;
  std::size_t pos = 0;
  std::size_t line = 0;
  while (pos < text.size()) {
    std::string_view rest = next_line(text, pos);
    ++line;
    while (!rest.empty() && is_blank(rest.front())) rest.remove_prefix(1);
    if (rest.empty() || rest.front() == kCommentMark) continue;
    const std::string at = file + ":" + std::to_string(line) + ": ";
    std::string_view words[D];
    int found = 0;
    for (std::string_view word = next_word(rest); !word.empty(); word = next_word(rest)) {
      if (found < D) words[found] = word;
      ++found;
    }
    if (found != D) {
      throw InvalidInput(at + "expected " + std::to_string(D) + " numbers (" + coordinates_named<D>() + "), found " +
                         std::to_string(found));
    }
    VecN<D> p{0.0f};
    for (int k = 0; k < D; ++k) {
      const std::string coordinate = std::string(1, "xyz"[k]) + " " + quoted(words[k]);
      switch (parse_float_word(words[k], p[k])) {
        case FloatWord::ok: break;
        case FloatWord::not_finite: throw InvalidInput(at + coordinate + " is not finite");
        case FloatWord::out_of_range: throw InvalidInput(at + coordinate + " is out of float range");
        case FloatWord::not_a_number: throw InvalidInput(at + coordinate + " is not a number");
      }
    }
    points.push_back(p);
  }
  return points;
}

template <int D>
std::vector<VecN<D>> load_points(const std::filesystem::path& path) {
  std::string why;
  const std::optional<std::string> text = read_text_file(path, why);
  if (!text) throw InvalidInput(path.string() + ": " + why);
  return parse_points<D>(*text, path);
}

template std::vector<Vec2> parse_points<2>(std::string_view, const std::filesystem::path&);
template std::vector<Vec3> parse_points<3>(std::string_view, const std::filesystem::path&);
template std::vector<Vec2> load_points<2>(const std::filesystem::path&);
template std::vector<Vec3> load_points<3>(const std::filesystem::path&);

}  // namespace collide::io
