#include <collide/draw/svg_draw.hpp>

#include <collide/core/error.hpp>
#include <collide/draw/bitmap_font.hpp>
#include <collide/draw/palette.hpp>

#include <charconv>
#include <cmath>
#include <fstream>

namespace collide {
namespace {

/// SVG font size per text-scale unit: a monospace font of size 10u advances about 6u per
/// character and has capitals about 7u tall, like the bitmap font (text is placed by its
/// baseline, kGlyphAscent below the top of its box).
constexpr int kFontSizePerScale = 10;

/// `v` with at most 2 decimals, trailing zeros and "-0" dropped: 12.5, 3, -0.25.
void put_number(std::string& out, float v) {
  if (std::fabs(v) < 0.005f) v = 0.0f;
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, 2);
  std::string_view s(buf, static_cast<size_t>(res.ptr - buf));
  if (s.find('.') != std::string_view::npos) {
    while (s.back() == '0') s.remove_suffix(1);
    if (s.back() == '.') s.remove_suffix(1);
  }
  out += s;
}

void put_point(std::string& out, Vec2 p) {
  put_number(out, p.x);
  out += ',';
  put_number(out, p.y);
}

/// Appends ` name="value"` for a number.
void put_attr(std::string& out, const char* name, float v) {
  out += ' ';
  out += name;
  out += "=\"";
  put_number(out, v);
  out += '"';
}

void put_hex(std::string& out, Color c) {
  static constexpr char kDigits[] = "0123456789abcdef";
  out += '#';
  for (const std::uint8_t v : {c.r, c.g, c.b}) {
    out += kDigits[v >> 4];
    out += kDigits[v & 15];
  }
}

/// ` fill="#rrggbb" fill-opacity="a"` (or ` fill="none"`), likewise for `stroke`.
void put_paint(std::string& out, const char* what, Color c) {
  out += ' ';
  out += what;
  out += "=\"";
  if (c.a == 0) {
    out += "none\"";
    return;
  }
  put_hex(out, c);
  out += '"';
  if (c.a < 255) {
    out += ' ';
    out += what;
    out += "-opacity=\"";
    put_number(out, static_cast<float>(c.a) / 255.0f);
    out += '"';
  }
}

/// Text with &, <, >, " escaped; invalid UTF-8 (one U+FFFD per ill-formed byte, as the bitmap
/// font counts columns), control characters and code points XML 1.0 forbids become U+FFFD, so
/// the document always parses.
void put_escaped(std::string& out, std::string_view text) {
  static constexpr std::string_view kReplacement = "\xef\xbf\xbd";
  for (size_t i = 0; i < text.size();) {
    const size_t start = i;
    const char32_t cp = next_code_point(text, i);
    switch (cp) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default:
        if (cp < 0x20 || (cp >= 0x7f && cp < 0xa0) || cp == 0xfffe || cp == 0xffff ||
            cp == kReplacementCharacter) {
          out += kReplacement;
        } else {
          out.append(text.substr(start, i - start));
        }
    }
  }
}

/// "role-" + the role's legend name in lower case, spaces as '-'.
std::string role_class(DrawRole role) {
  std::string s = "role-";
  for (const char* p = to_string(role); *p != '\0'; ++p) {
    const char c = *p;
    s += c == ' ' ? '-' : (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
  }
  return s;
}

class SvgWriter final : public PixelSink {
 public:
  std::string out;

  void begin(const PictureLayout& layout) override {
    scale_ = layout.text_scale;
    out += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\"";
    put_attr(out, "width", static_cast<float>(layout.width));
    put_attr(out, "height", static_cast<float>(layout.height));
    out += " viewBox=\"0 0 ";
    out += std::to_string(layout.width) + ' ' + std::to_string(layout.height);
    out += "\" font-family=\"DejaVu Sans Mono, Menlo, Consolas, monospace\"";
    put_attr(out, "font-size", static_cast<float>(kFontSizePerScale * scale_));
    out += ">\n<rect class=\"background\" width=\"100%\" height=\"100%\"";
    put_paint(out, "fill", kPictureBackground);
    out += "/>\n";
    if (!layout.title.empty()) put_text("title", layout.title_x, layout.title_y, layout.title, kPictureText);
  }

  void begin_panel(const PanelView& view) override {
    const auto& b = view.plot;
    out += "<rect class=\"frame\"";
    put_attr(out, "x", static_cast<float>(b.x) - 0.5f);
    put_attr(out, "y", static_cast<float>(b.y) - 0.5f);
    put_attr(out, "width", static_cast<float>(b.width) + 1.0f);
    put_attr(out, "height", static_cast<float>(b.height) + 1.0f);
    out += " fill=\"none\"";
    put_paint(out, "stroke", kPanelFrame);
    out += "/>\n";
    if (!view.title.empty()) {
      put_text("panel-title", b.x, b.y - kLineAdvance * scale_, view.title, kPictureText);
    }
    const std::string id = "plot" + std::to_string(panel_++);
    out += "<clipPath id=\"" + id + "\"><rect";
    put_attr(out, "x", static_cast<float>(b.x));
    put_attr(out, "y", static_cast<float>(b.y));
    put_attr(out, "width", static_cast<float>(b.width));
    put_attr(out, "height", static_cast<float>(b.height));
    out += "/></clipPath>\n<g class=\"panel\" clip-path=\"url(#" + id + ")\">\n";
  }
  void end_panel() override { out += "</g>\n"; }
  void begin_legend() override { out += "<g class=\"legend\">\n"; }
  void end_legend() override { out += "</g>\n"; }

  void polygon(std::span<const Vec2> v, float radius, DrawRole role) override {
    if (v.size() == 1) {
      circle(v[0], radius, role);
      return;
    }
    if (v.size() >= 3 && radius <= 0.0f) {
      open("polygon", role);
      out += " points=\"";
      for (size_t i = 0; i < v.size(); ++i) {
        if (i > 0) out += ' ';
        put_point(out, v[i]);
      }
      out += '"';
      solid_paint(role);
      out += "/>\n";
      return;
    }
    rounded_path(v, radius, role);
  }

  void circle(Vec2 c, float radius, DrawRole role) override {
    open("circle", role);
    put_attr(out, "cx", c.x);
    put_attr(out, "cy", c.y);
    put_attr(out, "r", radius);
    solid_paint(role);
    out += "/>\n";
  }

  void capsule(Vec2 a, Vec2 b, float radius, DrawRole role) override {
    if (a == b) {
      circle(a, radius, role);
      return;
    }
    const Vec2 ends[2] = {a, b};
    rounded_path(ends, radius, role);
  }

  void segment(Vec2 a, Vec2 b, DrawRole role) override {
    open("line", role);
    put_attr(out, "x1", a.x);
    put_attr(out, "y1", a.y);
    put_attr(out, "x2", b.x);
    put_attr(out, "y2", b.y);
    line_paint(role);
    out += "/>\n";
  }

  void arrow(const ArrowPixels& a, DrawRole role) override {
    // One path: the shaft (an open subpath, which fills nothing) and the closed head.
    open("path", role);
    out += " d=\"M";
    put_point(out, a.from);
    out += 'L';
    put_point(out, a.shaft_end);
    out += 'M';
    put_point(out, a.head_left);
    out += 'L';
    put_point(out, a.tip);
    out += 'L';
    put_point(out, a.head_right);
    out += "Z\"";
    const DrawStyle& s = draw_style(role);
    put_paint(out, "fill", s.stroke);
    line_paint(role);
    out += "/>\n";
  }

  void point(Vec2 p, DrawRole role) override {
    const DrawStyle& s = draw_style(role);
    if (s.marker == PointMarker::cross) {
      open("path", role);
      out += " d=\"M";
      put_point(out, p - Vec2{s.point_size, 0.0f});
      out += 'H';
      put_number(out, p.x + s.point_size);
      out += 'M';
      put_point(out, p - Vec2{0.0f, s.point_size});
      out += 'V';
      put_number(out, p.y + s.point_size);
      out += "\" fill=\"none\"";
      put_paint(out, "stroke", s.stroke);
      put_attr(out, "stroke-width", s.stroke_width);
      out += " stroke-linecap=\"round\"/>\n";
      return;
    }
    open("circle", role);
    put_attr(out, "cx", p.x);
    put_attr(out, "cy", p.y);
    put_attr(out, "r", s.point_size);
    put_paint(out, "fill", s.stroke);
    out += "/>\n";
  }

  void label(Vec2 top_left, std::string_view text, DrawRole role) override {
    open("text", role);
    put_attr(out, "x", top_left.x);
    put_attr(out, "y", top_left.y + static_cast<float>(kGlyphAscent * scale_));
    put_paint(out, "fill", draw_style(role).stroke);
    out += " stroke=\"#ffffff\" stroke-width=\"3\" stroke-linejoin=\"round\" paint-order=\"stroke\">";
    put_escaped(out, text);
    out += "</text>\n";
  }

  void text(int x, int y, std::string_view text) override {
    put_text("legend-text", x, y, text, kPictureText);
  }

  void end() override { out += "</svg>\n"; }

 private:
  void open(const char* element, DrawRole role) {
    out += '<';
    out += element;
    out += " class=\"" + role_class(role) + '"';
  }

  void solid_paint(DrawRole role) {
    const DrawStyle& s = draw_style(role);
    put_paint(out, "fill", s.fill);
    line_paint(role);
  }

  void line_paint(DrawRole role) {
    const DrawStyle& s = draw_style(role);
    put_paint(out, "stroke", s.stroke);
    put_attr(out, "stroke-width", s.stroke_width);
    out += " stroke-linejoin=\"round\" stroke-linecap=\"round\"";
    if (s.dashed) {
      out += " stroke-dasharray=\"";
      put_number(out, kDashLength);
      out += '"';
    }
  }

  /// The outline of the core grown by `radius`: each edge pushed out along its normal, joined
  /// by arcs of `radius` around the vertices (2 vertices: a capsule). Outward is to the right of
  /// the edges for a counter-clockwise core in (x right, y down) numbers, to the left for a
  /// clockwise one; the arcs turn the same way as the outline (SVG sweep flag 1: increasing
  /// angle).
  void rounded_path(std::span<const Vec2> core, float radius, DrawRole role) {
    const size_t n = core.size();
    float twice_area = 0.0f;
    for (size_t i = 0; i < n; ++i) twice_area += cross(core[i], core[(i + 1) % n]);
    const bool ccw = twice_area >= 0.0f;
    auto normal = [&](size_t i) {
      const Vec2 e = normalize_or_zero(core[(i + 1) % n] - core[i]);
      return ccw ? right_perp(e) : left_perp(e);
    };
    open("path", role);
    out += " d=\"M";
    put_point(out, core[0] + radius * normal(0));
    for (size_t i = 0; i < n; ++i) {
      const Vec2 next = core[(i + 1) % n];
      out += 'L';
      put_point(out, next + radius * normal(i));
      if (radius > 0.0f) {
        out += 'A';
        put_number(out, radius);
        out += ' ';
        put_number(out, radius);
        out += ccw ? " 0 0 1 " : " 0 0 0 ";
        put_point(out, next + radius * normal((i + 1) % n));
      }
    }
    out += "Z\"";
    solid_paint(role);
    out += "/>\n";
  }

  void put_text(const char* cls, int x, int y, std::string_view text, Color color) {
    out += "<text class=\"";
    out += cls;
    out += '"';
    put_attr(out, "x", static_cast<float>(x));
    put_attr(out, "y", static_cast<float>(y + kGlyphAscent * scale_));
    put_paint(out, "fill", color);
    out += '>';
    put_escaped(out, text);
    out += "</text>\n";
  }

  int scale_ = 1;
  int panel_ = 0;
};

}  // namespace

std::string render_svg(const Picture& picture) {
  SvgWriter writer;
  picture.replay(writer);
  return std::move(writer.out);
}

void save_svg(const Picture& picture, const std::filesystem::path& path) {
  const std::string text = render_svg(picture);
  std::ofstream file(path, std::ios::binary);
  if (!file) throw InvalidInput(path.string() + ": cannot open for writing (SVG)");
  file.write(text.data(), static_cast<std::streamsize>(text.size()));
  file.close();
  if (!file) throw InvalidInput(path.string() + ": cannot write SVG");
}

}  // namespace collide
