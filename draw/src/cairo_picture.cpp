#include <collide/draw/cairo_picture.hpp>

#include "picture_font.hpp"

#include <collide/core/error.hpp>

#include <cairo-pdf.h>
#include <cairo-svg.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <new>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

// Numbers handed to Cairo are doubles (its API takes nothing else); the picture's own are floats.

namespace collide {
namespace {

/// A whole circle, radians.
constexpr double kFullTurn = 2.0 * std::numbers::pi;

/// Throws for a failed Cairo `status` met while doing `what`: std::bad_alloc for a lack of
/// memory, InvalidInput for files that cannot be written, std::runtime_error otherwise.
[[noreturn]] void throw_cairo_error(cairo_status_t status, const std::string& what) {
  switch (status) {
    case CAIRO_STATUS_NO_MEMORY:
      throw std::bad_alloc();
    case CAIRO_STATUS_WRITE_ERROR:
    case CAIRO_STATUS_FILE_NOT_FOUND:
      throw InvalidInput(what + ": cannot be written (" + cairo_status_to_string(status) + ")");
    default:
      throw std::runtime_error("Cairo: " + what + ": " + cairo_status_to_string(status));
  }
}

void check(cairo_status_t status, const std::string& what) {
  if (status != CAIRO_STATUS_SUCCESS) throw_cairo_error(status, what);
}

/// Adds to the path of `cr` the outline of the convex polygon `core` (either winding) grown by
/// `radius` (> 0): each edge pushed out by `radius` along its outward normal, joined by arcs of
/// `radius` around the vertices. One vertex is a disc, two a capsule.
void add_rounded_outline(cairo_t* cr, std::span<const Vec2> core, float radius) {
  std::vector<Vec2> v;  // without repeated vertices: every edge has a direction
  v.reserve(core.size());
  for (const Vec2 p : core) {
    if (v.empty() || p != v.back()) v.push_back(p);
  }
  while (v.size() > 1 && v.back() == v.front()) v.pop_back();
  const std::size_t n = v.size();
  cairo_new_sub_path(cr);
  if (n == 1) {
    cairo_arc(cr, v[0].x, v[0].y, radius, 0.0, kFullTurn);
    cairo_close_path(cr);
    return;
  }
  // In image numbers (y down) a positive signed area means the outward normal of an edge is to
  // its right, and going round the outline turns the way angles increase (cairo_arc); a
  // negative one mirrors both. Collinear cores (two vertices) count as positive.
  float twice_area = 0.0f;
  for (std::size_t i = 0; i < n; ++i) twice_area += cross(v[i], v[(i + 1) % n]);
  const bool positive = twice_area >= 0.0f;
  auto normal = [&](std::size_t edge) {
    const Vec2 e = normalize_or_zero(v[(edge + 1) % n] - v[edge]);
    return positive ? right_perp(e) : left_perp(e);
  };
  for (std::size_t i = 0; i < n; ++i) {
    // Around vertex i, from the normal of the edge before it to the normal of the edge after
    // it: the unsigned angle between them, as a convex outline turns one way only.
    const Vec2 before = normal((i + n - 1) % n), after = normal(i);
    const double start = std::atan2(before.y, before.x);
    const double turn = std::acos(std::clamp(static_cast<double>(dot(before, after)), -1.0, 1.0));
    if (positive) {
      cairo_arc(cr, v[i].x, v[i].y, radius, start, start + turn);
    } else {
      cairo_arc_negative(cr, v[i].x, v[i].y, radius, start, start - turn);
    }
  }
  cairo_close_path(cr);
}

using SurfacePtr = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using ContextPtr = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

SurfacePtr make_surface(const std::filesystem::path& path, PictureFormat format, int width, int height) {
  switch (format) {
    case PictureFormat::png:
      return {cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height), cairo_surface_destroy};
    case PictureFormat::svg: {
      SurfacePtr surface(cairo_svg_surface_create(path.c_str(), width, height), cairo_surface_destroy);
      cairo_svg_surface_restrict_to_version(surface.get(), CAIRO_SVG_VERSION_1_1);
      cairo_svg_surface_set_document_unit(surface.get(), CAIRO_SVG_UNIT_PX);  // not Cairo's default, points
      return surface;
    }
    case PictureFormat::pdf:
      return {cairo_pdf_surface_create(path.c_str(), width, height), cairo_surface_destroy};
  }
  throw std::invalid_argument("save_drawing: not a PictureFormat");
}

const char* format_name(PictureFormat format) noexcept {
  switch (format) {
    case PictureFormat::png: return "PNG";
    case PictureFormat::svg: return "SVG";
    case PictureFormat::pdf: return "PDF";
  }
  return "picture";
}

}  // namespace

void set_source(cairo_t* cr, Color color) noexcept {
  constexpr double kChannelMax = 255.0;
  cairo_set_source_rgba(cr, color.r / kChannelMax, color.g / kChannelMax, color.b / kChannelMax,
                        color.a / kChannelMax);
}

void CairoSink::begin(const PictureLayout& layout) {
  cairo_save(cr_);
  cairo_rectangle(cr_, 0.0, 0.0, layout.width, layout.height);
  set_source(cr_, kPictureBackground);
  cairo_fill(cr_);
  use_picture_font(cr_, layout.font_size);
  cairo_set_line_cap(cr_, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_join(cr_, CAIRO_LINE_JOIN_ROUND);
  if (!layout.title.empty()) {
    set_source(cr_, kPictureText);
    show_text(layout.title_origin, layout.title);
  }
}

void CairoSink::begin_panel(const PanelView& view) {
  const PixelBox& b = view.plot;
  // The frame just outside the plot area, its stroke centred half its width out: it covers
  // whole pixels, so it is crisp.
  const double half = 0.5 * kPanelFrameWidth;
  cairo_save(cr_);
  cairo_set_line_join(cr_, CAIRO_LINE_JOIN_MITER);
  cairo_rectangle(cr_, b.x - half, b.y - half, b.width + 2.0 * half, b.height + 2.0 * half);
  cairo_set_line_width(cr_, kPanelFrameWidth);
  set_source(cr_, kPanelFrame);
  cairo_stroke(cr_);
  cairo_restore(cr_);
  if (!view.title.empty()) {
    set_source(cr_, kPictureText);
    show_text(view.title_origin, view.title);
  }
  cairo_save(cr_);
  cairo_rectangle(cr_, b.x, b.y, b.width, b.height);
  cairo_clip(cr_);
}

void CairoSink::end_panel() { cairo_restore(cr_); }

void CairoSink::polygon(std::span<const Vec2> vertices, float radius, DrawRole role) {
  if (vertices.empty()) return;
  if (radius > 0.0f || vertices.size() == 1) {
    add_rounded_outline(cr_, vertices, radius);
  } else {
    cairo_move_to(cr_, vertices[0].x, vertices[0].y);
    for (const Vec2 p : vertices.subspan(1)) cairo_line_to(cr_, p.x, p.y);
    cairo_close_path(cr_);
  }
  paint_solid(role);
}

void CairoSink::circle(Vec2 center, float radius, DrawRole role) { polygon({&center, 1}, radius, role); }

void CairoSink::capsule(Vec2 a, Vec2 b, float radius, DrawRole role) {
  const std::array<Vec2, 2> ends{a, b};
  polygon(ends, radius, role);
}

void CairoSink::segment(Vec2 a, Vec2 b, DrawRole role) {
  cairo_move_to(cr_, a.x, a.y);
  cairo_line_to(cr_, b.x, b.y);
  stroke_line(role, draw_style(role).dashed);
}

void CairoSink::arrow(const ArrowPixels& a, DrawRole role) {
  segment(a.from, a.shaft_end, role);
  cairo_move_to(cr_, a.head_left.x, a.head_left.y);
  cairo_line_to(cr_, a.tip.x, a.tip.y);
  cairo_line_to(cr_, a.head_right.x, a.head_right.y);
  cairo_close_path(cr_);
  set_source(cr_, draw_style(role).stroke);
  cairo_fill_preserve(cr_);
  stroke_line(role, false);
}

void CairoSink::point(Vec2 p, DrawRole role) {
  const DrawStyle& s = draw_style(role);
  if (s.marker == PointMarker::cross) {
    cairo_move_to(cr_, p.x - s.point_size, p.y);
    cairo_line_to(cr_, p.x + s.point_size, p.y);
    cairo_move_to(cr_, p.x, p.y - s.point_size);
    cairo_line_to(cr_, p.x, p.y + s.point_size);
    stroke_line(role, false);
    return;
  }
  cairo_new_sub_path(cr_);
  cairo_arc(cr_, p.x, p.y, s.point_size, 0.0, kFullTurn);
  set_source(cr_, s.stroke);
  cairo_fill(cr_);
}

void CairoSink::label(Vec2 origin, std::string_view text, DrawRole role) {
  const std::string terminated(text);
  cairo_move_to(cr_, origin.x, origin.y);
  cairo_text_path(cr_, terminated.c_str());
  cairo_set_line_width(cr_, kLabelHaloWidth);
  cairo_set_dash(cr_, nullptr, 0, 0.0);
  set_source(cr_, kPictureBackground);
  cairo_stroke(cr_);
  set_source(cr_, draw_style(role).stroke);
  show_text(origin, text);
}

void CairoSink::text(Vec2 origin, std::string_view text) {
  set_source(cr_, kPictureText);
  show_text(origin, text);
}

void CairoSink::end() { cairo_restore(cr_); }

void CairoSink::paint_solid(DrawRole role) {
  const DrawStyle& s = draw_style(role);
  if (s.fill.a > 0) {
    set_source(cr_, s.fill);
    cairo_fill_preserve(cr_);
  }
  stroke_line(role, s.dashed);
}

void CairoSink::stroke_line(DrawRole role, bool dashed) {
  const DrawStyle& s = draw_style(role);
  const double dash = kDashLength;
  cairo_set_dash(cr_, dashed ? &dash : nullptr, dashed ? 1 : 0, 0.0);
  cairo_set_line_width(cr_, s.stroke_width);
  set_source(cr_, s.stroke);
  cairo_stroke(cr_);
}

void CairoSink::show_text(Vec2 origin, std::string_view text) {
  const std::string terminated(text);  // Cairo takes NUL-terminated strings
  cairo_move_to(cr_, origin.x, origin.y);
  cairo_show_text(cr_, terminated.c_str());
}

void draw_picture(const Picture& picture, cairo_t* cr) {
  CairoSink sink(cr);
  picture.replay(sink);
  check(cairo_status(cr), "drawing a picture");
}

void save_drawing(const std::filesystem::path& path, PictureFormat format, int width, int height,
                  const std::function<void(cairo_t*)>& draw) {
  const std::string what = path.string();
  if (width < 1 || width > kMaxPictureSide || height < 1 || height > kMaxPictureSide) {
    throw InvalidInput(what + ": a picture of " + std::to_string(width) + " x " + std::to_string(height) +
                       " pixels: each side must be in [1, " + std::to_string(kMaxPictureSide) + "]");
  }
  const SurfacePtr surface = make_surface(path, format, width, height);
  check(cairo_surface_status(surface.get()), what);
  {
    const ContextPtr cr(cairo_create(surface.get()), cairo_destroy);
    check(cairo_status(cr.get()), what);
    draw(cr.get());
    check(cairo_status(cr.get()), what);
  }
  if (format == PictureFormat::png) {
    check(cairo_surface_write_to_png(surface.get(), path.c_str()), what + " (" + format_name(format) + ")");
  } else {
    cairo_surface_finish(surface.get());  // vector surfaces write their file as they finish
    check(cairo_surface_status(surface.get()), what + " (" + format_name(format) + ")");
  }
}

void save_picture(const Picture& picture, const std::filesystem::path& path, PictureFormat format) {
  const PictureLayout layout = picture.layout();
  save_drawing(path, format, layout.width, layout.height, [&](cairo_t* cr) { draw_picture(picture, cr); });
}

}  // namespace collide
