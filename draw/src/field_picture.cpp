// Pictures of a signed distance field: colour map, iso-lines and zero contour by marching
// squares, a scale bar and a legend, drawn with Cairo into a PNG.

#include <collide/draw/field_picture.hpp>

#include <collide/sdf/contour.hpp>

#include "picture_font.hpp"

#include <collide/core/error.hpp>
#include <collide/draw/cairo_picture.hpp>
#include <collide/draw/picture.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

namespace collide {
namespace {

/// Font size of the title and legend, pixels.
constexpr double kFont = 2.0 * kFontSizePerTextScale;
/// Height of a line of text, in font sizes.
constexpr double kLineHeight = 1.6;
/// Space around the plot and between the blocks, pixels.
constexpr double kPad = 12.0;
/// The picture is at least this wide, so the legend has room beside a narrow plot.
constexpr int kMinFieldPictureWidth = 560;
/// Smallest plot side, pixels.
constexpr int kMinPlotSide = 16;
/// Line widths, pixels.
constexpr double kZeroContourWidth = 2.5;
constexpr double kIsoLineWidth = 1.0;
/// Colours reach kFieldFar at about this fraction of the slice's longer extent from the surface
/// (1 - e^-1 of the way at this distance).
constexpr float kFadeFraction = 0.2f;
/// Most iso-lines on either side of the surface: the spacing doubles until they fit.
constexpr int kMaxIsoLinesPerSide = 64;
/// The scale bar's length aims at this fraction of the plot's width.
constexpr double kScaleBarFraction = 0.2;
/// Side of a legend swatch and the gap after an item, in font sizes.
constexpr double kSwatch = 1.0;
constexpr double kItemGap = 1.5;

struct SurfaceDeleter {
  void operator()(cairo_surface_t* s) const noexcept { cairo_surface_destroy(s); }
};
using SurfacePtr = std::unique_ptr<cairo_surface_t, SurfaceDeleter>;

void check_slice(const FieldSlice& s) {
  if (s.width < 2 || s.height < 2) {
    throw InvalidInput("field picture: a slice of " + std::to_string(s.width) + " x " + std::to_string(s.height) +
                       " samples (need at least 2 x 2)");
  }
  if (s.values.size() != static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height)) {
    throw InvalidInput("field picture: " + std::to_string(s.values.size()) + " values for " + std::to_string(s.width) +
                       " x " + std::to_string(s.height) + " samples");
  }
  if (!(s.spacing > 0.0f) || !std::isfinite(s.spacing) || !is_finite(s.origin)) {
    throw InvalidInput("field picture: spacing and origin must be finite, spacing > 0");
  }
  for (std::size_t i = 0; i < s.values.size(); ++i) {
    if (!std::isfinite(s.values[i])) throw InvalidInput("field picture: value " + std::to_string(i) + " is not finite");
  }
}

/// The bilinear value of the slice at grid coordinates (x, y), clamped to the grid.
float bilinear(const FieldSlice& s, float x, float y) {
  x = std::clamp(x, 0.0f, static_cast<float>(s.width - 1));
  y = std::clamp(y, 0.0f, static_cast<float>(s.height - 1));
  const int i = std::min(static_cast<int>(x), s.width - 2);
  const int j = std::min(static_cast<int>(y), s.height - 2);
  const float fx = x - static_cast<float>(i), fy = y - static_cast<float>(j);
  const auto at = [&](int a, int b) { return s.values[static_cast<std::size_t>(b) * s.width + a]; };
  const float bottom = at(i, j) + fx * (at(i + 1, j) - at(i, j));
  const float top = at(i, j + 1) + fx * (at(i + 1, j + 1) - at(i, j + 1));
  return bottom + fy * (top - bottom);
}

std::uint8_t mix(std::uint8_t a, std::uint8_t b, float t) {
  return static_cast<std::uint8_t>(std::lround(static_cast<float>(a) + t * (static_cast<float>(b) - static_cast<float>(a))));
}

/// A round length (1, 2 or 5 times a power of ten) near `target`.
double round_length(double target) {
  const double power = std::pow(10.0, std::floor(std::log10(target)));
  for (const double step : {1.0, 2.0, 5.0}) {
    if (step * power * 1.5 >= target) return step * power;
  }
  return 10.0 * power;
}

/// `x` for the legend: 4 significant digits.
std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", x);
  return buf;
}

}  // namespace

std::vector<std::array<Vec2, 2>> contour_segments(const FieldSlice& s, float level) {
  check_slice(s);
  std::vector<std::array<Vec2, 2>> out;
  march_squares(
      s.width, s.height, s.origin, s.spacing, level,
      [&](int i, int j) { return s.values[static_cast<std::size_t>(j) * static_cast<std::size_t>(s.width) + i]; },
      [&](Vec2 a, Vec2 b) { out.push_back({a, b}); });
  return out;
}

FieldPictureSize save_field_picture(const FieldSlice& s, const FieldPictureOptions& o, const std::filesystem::path& path) {
  check_slice(s);
  if (o.size < kMinPlotSide || o.size > kMaxPictureSide) {
    throw InvalidInput(path.string() + ": field picture size " + std::to_string(o.size) + " not in [" +
                       std::to_string(kMinPlotSide) + ", " + std::to_string(kMaxPictureSide) + "]");
  }
  if (!(o.iso_spacing >= 0.0f) || !std::isfinite(o.iso_spacing)) {
    throw InvalidInput(path.string() + ": iso-line spacing must be finite and >= 0");
  }
  // ---- layout: title, plot, one or two legend rows ----
  const Vec2 extent = s.spacing * Vec2{static_cast<float>(s.width - 1), static_cast<float>(s.height - 1)};
  const double scale = static_cast<double>(o.size) / static_cast<double>(std::max(extent.x, extent.y));  // pixels per unit
  const int plot_w = std::max(kMinPlotSide, static_cast<int>(std::lround(extent.x * scale)));
  const int plot_h = std::max(kMinPlotSide, static_cast<int>(std::lround(extent.y * scale)));
  const double line = kLineHeight * kFont;
  const int width = std::max(kMinFieldPictureWidth, plot_w + 2 * static_cast<int>(kPad));
  const double plot_x = std::floor(0.5 * (width - plot_w));
  const double plot_y = std::ceil(kPad + (o.title.empty() ? 0.0 : line));  // whole pixels: the plot is not resampled

  float lo = s.values[0], hi = s.values[0];
  for (const float v : s.values) lo = std::min(lo, v), hi = std::max(hi, v);
  float iso = o.iso_spacing > 0.0f ? o.iso_spacing : kFieldIsoSpacingVoxels * s.spacing;
  while (std::max(-lo, hi) / iso > static_cast<float>(kMaxIsoLinesPerSide)) iso *= 2.0f;

  // Legend items: swatch kind (0 fill, 1 line) and text.
  struct Item {
    Color color;
    bool line;
    double width;
    std::string text;
  };
  std::vector<Item> items = {{kFieldInside, false, 0.0, "inside (< 0)"},
                             {kFieldOutside, false, 0.0, "outside (> 0)"},
                             {kFieldZeroContour, true, kZeroContourWidth, "surface (0)"},
                             {kFieldIsoLine, true, kIsoLineWidth, "every " + number(iso) + " " + o.unit}};
  const double bar_world = round_length(kScaleBarFraction * extent.x);
  const double bar_px = bar_world * scale;
  const std::string bar_text = number(bar_world) + " " + o.unit + " (" + o.horizontal_axis + " right, " +
                               o.vertical_axis + (o.vertical_down ? " down)" : " up)");
  const TextMeasurer measure(kFont);
  double x = kPad + bar_px + 0.5 * kFont + measure.width(bar_text) + kItemGap * kFont;
  int rows = 1;
  std::vector<std::pair<double, int>> places;  // x and row of each item
  for (const Item& item : items) {
    const double w = (kSwatch + 0.5) * kFont + measure.width(item.text);
    if (x + w > width - kPad && x > kPad) x = kPad, ++rows;
    places.emplace_back(x, rows - 1);
    x += w + kItemGap * kFont;
  }
  const double legend_y = plot_y + plot_h + kPad;
  const int height = static_cast<int>(std::ceil(legend_y + rows * line + kPad));

  // ---- the colour-mapped plot, one bilinear sample per pixel ----
  SurfacePtr plot(cairo_image_surface_create(CAIRO_FORMAT_RGB24, plot_w, plot_h));
  if (cairo_surface_status(plot.get()) != CAIRO_STATUS_SUCCESS) throw std::bad_alloc();
  {
    unsigned char* data = cairo_image_surface_get_data(plot.get());
    const int stride = cairo_image_surface_get_stride(plot.get());
    const float fade = kFadeFraction * std::max(extent.x, extent.y);
    const float to_grid_x = extent.x / static_cast<float>(plot_w) / s.spacing;  // grid steps per pixel
    const float to_grid_y = extent.y / static_cast<float>(plot_h) / s.spacing;
    for (int py = 0; py < plot_h; ++py) {
      auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(py) * stride);
      const float gy = (o.vertical_down ? static_cast<float>(py) + 0.5f : static_cast<float>(plot_h - py) - 0.5f) * to_grid_y;
      for (int px = 0; px < plot_w; ++px) {
        const float d = bilinear(s, (static_cast<float>(px) + 0.5f) * to_grid_x, gy);
        const Color base = d < 0.0f ? kFieldInside : kFieldOutside;
        const float t = 1.0f - std::exp(-std::fabs(d) / fade);
        const Color c{mix(base.r, kFieldFar.r, t), mix(base.g, kFieldFar.g, t), mix(base.b, kFieldFar.b, t), 255};
        row[px] = (std::uint32_t{c.r} << 16) | (std::uint32_t{c.g} << 8) | std::uint32_t{c.b};
      }
    }
    cairo_surface_mark_dirty(plot.get());
  }

  // World (in the plane) to picture pixels.
  const auto to_pixel = [&](Vec2 w) {
    const double u = (w.x - s.origin.x) * (plot_w / static_cast<double>(extent.x));
    const double v = (w.y - s.origin.y) * (plot_h / static_cast<double>(extent.y));
    return std::pair{plot_x + u, o.vertical_down ? plot_y + v : plot_y + plot_h - v};
  };
  const auto stroke_contour = [&](cairo_t* cr, float level) {
    for (const auto& seg : contour_segments(s, level)) {
      const auto [ax, ay] = to_pixel(seg[0]);
      const auto [bx, by] = to_pixel(seg[1]);
      cairo_move_to(cr, ax, ay);
      cairo_line_to(cr, bx, by);
    }
    cairo_stroke(cr);
  };

  save_drawing(path, PictureFormat::png, width, height, [&](cairo_t* cr) {
    set_source(cr, kPictureBackground);
    cairo_paint(cr);
    cairo_set_source_surface(cr, plot.get(), plot_x, plot_y);
    cairo_paint(cr);
    cairo_save(cr);
    cairo_rectangle(cr, plot_x, plot_y, plot_w, plot_h);
    cairo_clip(cr);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    cairo_set_line_width(cr, kIsoLineWidth);
    set_source(cr, kFieldIsoLine);
    for (float level = -iso; level >= lo; level -= iso) stroke_contour(cr, level);
    for (float level = iso; level <= hi; level += iso) stroke_contour(cr, level);
    cairo_set_line_width(cr, kZeroContourWidth);
    set_source(cr, kFieldZeroContour);
    stroke_contour(cr, 0.0f);
    cairo_restore(cr);
    cairo_set_line_width(cr, 1.0);
    set_source(cr, kPanelFrame);
    cairo_rectangle(cr, plot_x + 0.5, plot_y + 0.5, plot_w - 1.0, plot_h - 1.0);
    cairo_stroke(cr);

    use_picture_font(cr, kFont);
    set_source(cr, kPictureText);
    if (!o.title.empty()) {
      cairo_move_to(cr, kPad, kPad + 0.75 * line);
      cairo_show_text(cr, clean_text(o.title).c_str());
    }
    // Scale bar with end ticks, then its length.
    const double mid = legend_y + 0.5 * line;
    const double tick = 0.35 * kFont;
    cairo_set_line_width(cr, 2.0);
    cairo_move_to(cr, kPad, mid - tick);
    cairo_line_to(cr, kPad, mid + tick);
    cairo_move_to(cr, kPad, mid);
    cairo_line_to(cr, kPad + bar_px, mid);
    cairo_move_to(cr, kPad + bar_px, mid - tick);
    cairo_line_to(cr, kPad + bar_px, mid + tick);
    cairo_stroke(cr);
    cairo_move_to(cr, kPad + bar_px + 0.5 * kFont, mid + 0.35 * kFont);
    cairo_show_text(cr, clean_text(bar_text).c_str());
    for (std::size_t k = 0; k < items.size(); ++k) {
      const Item& item = items[k];
      const double ix = places[k].first;
      const double iy = legend_y + places[k].second * line + 0.5 * line;
      const double side = kSwatch * kFont;
      set_source(cr, item.color);
      if (item.line) {
        cairo_set_line_width(cr, item.width);
        cairo_move_to(cr, ix, iy);
        cairo_line_to(cr, ix + side, iy);
        cairo_stroke(cr);
      } else {
        cairo_rectangle(cr, ix, iy - 0.5 * side, side, side);
        cairo_fill(cr);
      }
      set_source(cr, kPictureText);
      cairo_move_to(cr, ix + side + 0.5 * kFont, iy + 0.35 * kFont);
      cairo_show_text(cr, clean_text(item.text).c_str());
    }
  });
  return {width, height, static_cast<int>(plot_x), static_cast<int>(plot_y), plot_w, plot_h};
}

}  // namespace collide
