// `collide cast [FILE] [--question JSON] [--svg FILE] [--png FILE] [--pdf FILE]`: answers one shape cast (a
// `toi` question of the query protocol) and draws it: the shapes' motion, and the ray from the
// origin into the Minkowski difference A - B that the answer comes from.

#include "cast.hpp"
#include "command_errors.hpp"
#include "commands.hpp"
#include "query.hpp"

#include <collide/core/error.hpp>
#include <collide/draw/cairo_picture.hpp>

#include <array>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <utility>

namespace collide::cli {
namespace {

struct CastOptions {
  std::string file;      ///< the question, one JSON object ("-": standard input)
  std::string question;  ///< the question inline (instead of a file)
  std::string svg;
  std::string png;
  std::string pdf;
  int width = 1000;
  int text_scale = 2;
};

/// All of `in`, at most kMaxQueryLineBytes (a question is one line of `collide query`): a longer
/// input (`cat /dev/zero |`) is an error naming the limit, not a read without end.
std::string read_bounded(std::istream& in, const std::string& name) {
  std::string text;
  std::array<char, 1 << 16> buffer{};
  while (in.read(buffer.data(), static_cast<std::streamsize>(buffer.size())) || in.gcount() > 0) {
    const auto got = static_cast<std::size_t>(in.gcount());
    if (text.size() + got > kMaxQueryLineBytes) {
      throw InvalidInput(name + ": longer than " + std::to_string(kMaxQueryLineBytes) +
                         " bytes (the limit of a question, 16 MiB)");
    }
    text.append(buffer.data(), got);
  }
  if (in.bad()) throw InvalidInput(name + ": read error");
  return text;
}

/// Where the question comes from, for messages: "--question", "standard input" or the file.
std::string question_source(const CastOptions& o) {
  if (!o.question.empty()) return "--question";
  if (o.file.empty() || o.file == "-") return "standard input";
  return o.file;
}

std::string read_question(const CastOptions& o) {
  if (!o.question.empty()) return o.question;
  if (o.file.empty() || o.file == "-") return read_bounded(std::cin, "standard input");
  require_input_file(o.file);
  std::ifstream in(o.file, std::ios::binary);
  if (!in) throw InvalidInput(o.file + ": cannot be read");
  return read_bounded(in, o.file);
}

int run_cast(const CastOptions& o) {
  if (!o.png.empty()) require_output_folder("--png", o.png);
  if (!o.svg.empty()) require_output_folder("--svg", o.svg);
  if (!o.pdf.empty()) require_output_folder("--pdf", o.pdf);
  const CastQuestion q = parse_cast_question(read_question(o));
  PictureOptions options;
  options.width = o.width;
  options.text_scale = o.text_scale;
  Picture picture(options);
  const CastPicture cast = draw_cast(picture, q);
  const ShapeCastResult& r = cast.result;
  std::printf("%s\n", describe(r).c_str());
  if (r.hit) {
    std::printf("  point     %g %g\n", static_cast<double>(r.point.x), static_cast<double>(r.point.y));
    std::printf("  normal    %g %g  (from A to B)\n", static_cast<double>(r.normal.x), static_cast<double>(r.normal.y));
  }
  std::printf("  A - B     %zu vertices, radius %g, signed distance to the origin %g\n",
              cast.difference.vertices.size(), static_cast<double>(cast.difference.radius),
              static_cast<double>(cast.difference.signed_distance_to_origin()));
  std::printf("  ray       vb - va = %g %g\n", static_cast<double>(cast.ray.x), static_cast<double>(cast.ray.y));
  const PictureLayout layout = picture.layout();
  for (const auto& [path, format] : {std::pair{o.svg, PictureFormat::svg}, std::pair{o.png, PictureFormat::png},
                                     std::pair{o.pdf, PictureFormat::pdf}}) {
    if (path.empty()) continue;
    save_picture(picture, path, format);
    std::printf("wrote %s (%d x %d)\n", path.c_str(), layout.width, layout.height);
  }
  return r.status == QueryStatus::max_iterations ? 3 : 0;
}

}  // namespace

void register_cast_command(CLI::App& app) {
  auto options = std::make_shared<CastOptions>();
  CLI::App* cmd = app.add_subcommand(
      "cast", "Answer one shape cast (a \"toi\" question) and draw it: the motion, and the ray into A - B");
  cmd->add_option("file", options->file,
                  "The question: one JSON object with a, xa, va, b, xb, vb as in `collide query` "
                  "(default: standard input)");
  cmd->add_option("--question", options->question, "The question inline, instead of a file");
  cmd->add_option("--svg", options->svg, "Write the picture as SVG");
  cmd->add_option("--png", options->png, "Write the picture as PNG");
  cmd->add_option("--pdf", options->pdf, "Write the picture as PDF");
  cmd->add_option("--width", options->width, "Picture width, pixels")
      ->capture_default_str()->check(CLI::Range(kMinPictureWidth, kMaxPictureSide));
  cmd->add_option("--text-scale", options->text_scale, "Text size, 7 pixels per step, and the spacing around it")
      ->capture_default_str()->check(CLI::Range(1, kMaxTextScale));
  cmd->footer("Example:\n  collide cast --svg cast.svg --png cast.png --question '{\"a\": {\"type\": \"box\", "
              "\"half\": [1, 0.5]}, \"va\": [6, 1], \"b\": {\"type\": \"circle\", \"radius\": 1}, "
              "\"xb\": {\"p\": [5, 0]}, \"vb\": [0, 0]}'");
  cmd->callback([options]() {
    const int code = run_guarded("cast", question_source(*options), [&] { return run_cast(*options); });
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace collide::cli
