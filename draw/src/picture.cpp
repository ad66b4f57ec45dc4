#include <collide/draw/picture.hpp>

#include "picture_font.hpp"

#include <collide/core/error.hpp>
#include <collide/draw/palette.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace collide {
namespace {

/// How far beyond its plot area a panel's geometry is still sent (pixels): wide enough for any
/// stroke, marker or arrow head to reach into the plot, small enough that clipped coordinates
/// stay modest numbers in an SVG file.
constexpr double kCullMargin = 64.0;

/// World half-size given to content of no extent at all (a lone point) before the margin.
constexpr float kLonePointHalfSize = 0.5f;

/// A generous bound on the advance of text per byte of its UTF-8, ems: ASCII glyphs advance
/// less than one em each, and wider glyphs take 2 to 4 bytes.
constexpr double kMaxEmsPerByte = 2.0;
/// An upper bound on the height of a line of text, in ems (ascent plus descent).
constexpr double kMaxLineEms = 2.0;

using DVec2 = glm::dvec2;

/// Clips segment a-b to the box [lo, hi] (Liang-Barsky 1984). False when nothing is left. In
/// doubles: a ray's far end may be beyond float range once scaled to pixels.
bool clip_segment(DVec2& a, DVec2& b, DVec2 lo, DVec2 hi) noexcept {
  double t0 = 0.0, t1 = 1.0;
  const DVec2 d = b - a;
  for (int axis = 0; axis < 2; ++axis) {
    const double p[2] = {-d[axis], d[axis]};
    const double q[2] = {a[axis] - lo[axis], hi[axis] - a[axis]};
    for (int k = 0; k < 2; ++k) {
      if (p[k] == 0.0) {
        if (q[k] < 0.0) return false;
        continue;
      }
      const double t = q[k] / p[k];
      if (p[k] < 0.0) t0 = std::max(t0, t);
      else t1 = std::min(t1, t);
    }
  }
  if (!(t0 <= t1)) return false;
  const DVec2 start = a;
  a = start + t0 * d;
  b = start + t1 * d;
  return true;
}

/// `view.to_image(p)` in doubles.
DVec2 to_image_exact(const PanelView& view, Vec2 p) noexcept {
  const DVec2 center{view.plot.x + 0.5 * view.plot.width, view.plot.y + 0.5 * view.plot.height};
  const DVec2 offset = DVec2(p) - DVec2(view.world.center());
  return center + static_cast<double>(view.scale) * DVec2{offset.x, view.y_up ? -offset.y : offset.y};
}

/// The world rectangle a panel shows: given, or its content grown by the margin.
Aabb fit_world(const Aabb& content, bool empty, float margin) {
  if (empty) return {{-1.0f, -1.0f}, {1.0f, 1.0f}};
  const Vec2 size = content.size();
  float larger = std::max(size.x, size.y);
  if (!(larger > 0.0f)) larger = 2.0f * kLonePointHalfSize;
  return fatten(content, margin * larger);
}

bool finite_positive(float v) { return std::isfinite(v) && v > 0.0f; }

}  // namespace

Vec2 PanelView::to_image(Vec2 p) const noexcept {
  const Vec2 plot_center{static_cast<float>(plot.x) + 0.5f * static_cast<float>(plot.width),
                         static_cast<float>(plot.y) + 0.5f * static_cast<float>(plot.height)};
  const Vec2 offset = p - world.center();
  return plot_center + scale * Vec2{offset.x, y_up ? -offset.y : offset.y};
}

Picture::Picture(PictureOptions options) : options_(std::move(options)) {
  const PictureOptions& o = options_;
  if (o.width < kMinPictureWidth || o.width > kMaxPictureSide) {
    throw InvalidInput("picture width " + std::to_string(o.width) + ": must be in [" +
                       std::to_string(kMinPictureWidth) + ", " + std::to_string(kMaxPictureSide) + "]");
  }
  if (o.plot_height < 0 || o.plot_height > kMaxPictureSide) {
    throw InvalidInput("picture plot_height " + std::to_string(o.plot_height) + ": must be in [0, " +
                       std::to_string(kMaxPictureSide) + "] (0: from the content)");
  }
  if (o.text_scale < 1 || o.text_scale > kMaxTextScale) {
    throw InvalidInput("picture text_scale " + std::to_string(o.text_scale) + ": must be in [1, " +
                       std::to_string(kMaxTextScale) + "]");
  }
  if (!(o.margin >= 0.0f && o.margin <= kMaxPictureMargin)) {
    throw InvalidInput("picture margin " + std::to_string(o.margin) + ": must be in [0, " +
                       std::to_string(kMaxPictureMargin) + "]");
  }
  if (o.world && !(is_valid(*o.world) && o.world->max.x > o.world->min.x && o.world->max.y > o.world->min.y)) {
    throw InvalidInput("picture world rectangle: must be finite with min < max on both axes");
  }
}

void Picture::begin_panel(std::string_view title, std::optional<Aabb> world) {
  if (world && !(is_valid(*world) && world->max.x > world->min.x && world->max.y > world->min.y)) {
    throw InvalidInput("panel \"" + std::string(title) +
                       "\" world rectangle: must be finite with min < max on both axes");
  }
  panels_.push_back(Panel{clean_text(title), world, {}, {}, true});
}

Picture::Panel& Picture::current_panel() {
  if (panels_.empty()) panels_.push_back(Panel{});
  return panels_.back();
}

bool Picture::accept(std::span<const Vec2> points, float radius) {
  bool ok = !points.empty() && std::isfinite(radius) && radius >= 0.0f;
  for (const Vec2 p : points) ok = ok && is_finite(p);
  if (!ok) ++skipped_;
  return ok;
}

void Picture::record(Kind kind, DrawRole role, std::span<const Vec2> points, float radius,
                     std::string_view text) {
  if (static_cast<int>(role) >= kDrawRoleCount) {
    ++skipped_;
    return;
  }
  if (!accept(points, radius)) return;
  Panel& panel = current_panel();
  Aabb box{points[0], points[0]};
  for (const Vec2 p : points) box = merge(box, Aabb{p, p});
  box = fatten(box, radius);
  panel.bounds = panel.empty ? box : merge(panel.bounds, box);
  panel.empty = false;
  Item item{kind, role, static_cast<std::uint32_t>(points_.size()),
            static_cast<std::uint32_t>(points.size()), radius, 0};
  points_.insert(points_.end(), points.begin(), points.end());
  if (kind == Kind::label) {
    item.text = static_cast<std::uint32_t>(texts_.size());
    texts_.push_back(clean_text(text));
  }
  panel.items.push_back(item);
  roles_mask_ |= 1u << static_cast<unsigned>(role);
}

void Picture::draw_polygon(std::span<const Vec2> vertices, float radius, DrawRole role) {
  record(Kind::polygon, role, vertices, radius);
}
void Picture::draw_circle(Vec2 center, float radius, DrawRole role) {
  record(Kind::circle, role, {&center, 1}, radius);
}
void Picture::draw_capsule(Vec2 a, Vec2 b, float radius, DrawRole role) {
  const std::array<Vec2, 2> ends{a, b};
  record(Kind::capsule, role, ends, radius);
}
void Picture::draw_segment(Vec2 a, Vec2 b, DrawRole role) {
  const std::array<Vec2, 2> ends{a, b};
  record(Kind::segment, role, ends, 0.0f);
}
void Picture::draw_arrow(Vec2 from, Vec2 to, DrawRole role) {
  const std::array<Vec2, 2> ends{from, to};
  record(Kind::arrow, role, ends, 0.0f);
}
void Picture::draw_point(Vec2 p, DrawRole role) { record(Kind::point, role, {&p, 1}, 0.0f); }
void Picture::draw_label(Vec2 at, std::string_view text, DrawRole role) {
  record(Kind::label, role, {&at, 1}, 0.0f, text);
}

std::vector<DrawRole> Picture::roles_drawn() const {
  std::vector<DrawRole> roles;
  for (int r = 0; r < kDrawRoleCount; ++r) {
    if (roles_mask_ & (1u << r)) roles.push_back(static_cast<DrawRole>(r));
  }
  return roles;
}

PictureLayout Picture::layout() const {
  const PictureOptions& o = options_;
  const int u = o.text_scale;
  const int pad = kPicturePadding * u;
  const int gap = kPanelGap * u;
  PictureLayout out;
  out.width = o.width;
  out.font_size = kFontSizePerTextScale * static_cast<float>(u);
  const TextMeasurer measure(out.font_size);
  const auto ascent = static_cast<float>(measure.ascent());
  // One line of text, in whole pixels so that the plot areas below start on a pixel.
  const int line = static_cast<int>(std::ceil(measure.ascent() + measure.descent()));
  int y = pad;

  std::string title = clean_text(o.title);
  if (skipped_ > 0) {
    title += (title.empty() ? "" : "  ") + std::string("[") + std::to_string(skipped_) +
             " bad draw call" + (skipped_ == 1 ? "" : "s") + " skipped]";
  }
  if (!title.empty()) {
    out.title = measure.fit(title, o.width - 2 * pad);
    out.title_origin = {static_cast<float>(pad), static_cast<float>(y) + ascent};
    y += line + kTitleGap * u;
  }

  // Panels: equal widths across the image; plot height from the tallest world rectangle.
  const int n = std::max<int>(1, static_cast<int>(panels_.size()));
  const int panel_width = std::max(1, (o.width - 2 * pad - (n - 1) * gap) / n);
  bool any_title = false;
  float aspect = kMinPlotAspect;
  out.panels.resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    PanelView& view = out.panels[static_cast<size_t>(i)];
    view.y_up = o.y_up;
    if (i < static_cast<int>(panels_.size())) {
      const Panel& p = panels_[static_cast<size_t>(i)];
      view.title = measure.fit(p.title, panel_width);
      view.world = p.world ? *p.world : o.world ? *o.world : fit_world(p.bounds, p.empty, o.margin);
    } else {
      view.world = o.world ? *o.world : fit_world({}, true, o.margin);
    }
    any_title = any_title || !view.title.empty();
    const Vec2 size = view.world.size();
    aspect = std::max(aspect, size.x > 0.0f ? size.y / size.x : kMaxPlotAspect);
  }
  const float panel_title_baseline = static_cast<float>(y) + ascent;
  if (any_title) y += line;
  const float pw = static_cast<float>(panel_width);
  const int plot_height =
      o.plot_height > 0 ? o.plot_height
                        : static_cast<int>(std::lround(pw * std::clamp(aspect, kMinPlotAspect, kMaxPlotAspect)));
  for (int i = 0; i < n; ++i) {
    PanelView& view = out.panels[static_cast<size_t>(i)];
    view.plot = {pad + i * (panel_width + gap), y, panel_width, plot_height};
    view.title_origin = {static_cast<float>(view.plot.x), panel_title_baseline};
    // Uniform scale: the world rectangle fits the plot on its tighter axis. An axis of no
    // extent (float rounding far from the origin) does not constrain it.
    const Vec2 size = view.world.size();
    const float sx = size.x > 0.0f ? pw / size.x : INFINITY;
    const float sy = size.y > 0.0f ? static_cast<float>(plot_height) / size.y : INFINITY;
    view.scale = std::min(sx, sy);
    if (!finite_positive(view.scale)) view.scale = 1.0f;
  }
  y += plot_height;

  if (o.legend && roles_mask_ != 0) {
    // Rows of entries (swatch, gap, name), wrapped where the next would pass the padding; each
    // swatch centred on the height of its name's capitals.
    y += pad;
    const int swatch_width = kSwatchWidth * u, swatch_height = kSwatchHeight * u;
    const int name_start = swatch_width + kSwatchTextGap * u;
    int x = pad;
    int row_y = y;
    for (const DrawRole role : roles_drawn()) {
      const auto name_width = static_cast<float>(measure.width(to_string(role)));
      const int entry = name_start + static_cast<int>(std::ceil(name_width));
      if (x > pad && x + entry > o.width - pad) {
        x = pad;
        row_y += line;
      }
      const float baseline = static_cast<float>(row_y) + ascent;
      const auto swatch_y = static_cast<int>(
          std::lround(baseline - 0.5 * measure.cap_height() - 0.5 * static_cast<double>(swatch_height)));
      out.legend.push_back({role, {x, swatch_y, swatch_width, swatch_height},
                            {static_cast<float>(x + name_start), baseline}, name_width});
      x += entry + gap;
    }
    y = row_y + line;
  }
  out.height = y + pad;
  return out;
}

void Picture::replay_item(const Item& item, const PanelView& view, PixelSink& sink,
                          std::vector<Vec2>& mapped) const {
  // Cull what cannot reach the plot area; clip lines to near it, in doubles, so rays to far
  // away stay drawable and every coordinate sent is a modest number.
  const DVec2 lo{view.plot.x - kCullMargin, view.plot.y - kCullMargin};
  const DVec2 hi{view.plot.x + view.plot.width + kCullMargin, view.plot.y + view.plot.height + kCullMargin};
  if (item.kind == Kind::segment || item.kind == Kind::arrow) {
    DVec2 a = to_image_exact(view, points_[item.first]);
    DVec2 b = to_image_exact(view, points_[item.first + 1]);
    const DVec2 tip = b;
    if (!clip_segment(a, b, lo, hi)) return;
    const Vec2 from(a), to(b);
    if (item.kind == Kind::segment || b != tip || from == to) {  // an arrow whose head is off the plot: its shaft
      sink.segment(from, to, item.role);
      return;
    }
    const float len = distance(from, to);
    const float head = std::min(kArrowHeadLength, 0.5f * len);
    const float half_width = kArrowHeadHalfWidth * head / kArrowHeadLength;
    const Vec2 dir = (to - from) / len;
    const Vec2 base = to - head * dir;
    const Vec2 side = half_width * left_perp(dir);
    sink.arrow({from, base, to, base + side, base - side}, item.role);
    return;
  }
  mapped.resize(item.count);
  DVec2 box_lo{INFINITY}, box_hi{-INFINITY};
  for (std::uint32_t i = 0; i < item.count; ++i) {
    const DVec2 p = to_image_exact(view, points_[item.first + i]);
    box_lo = glm::min(box_lo, p);
    box_hi = glm::max(box_hi, p);
    mapped[i] = Vec2(p);
  }
  const float radius = item.radius * view.scale;
  double reach = radius;
  if (item.kind == Kind::label) {
    // Far enough for any of the text to reach into the plot: its width is bounded by its bytes.
    const double em = kFontSizePerTextScale * static_cast<double>(options_.text_scale);
    reach = kLabelOffset + (static_cast<double>(texts_[item.text].size()) * kMaxEmsPerByte + kMaxLineEms) * em;
  }
  if (!(box_hi.x + reach >= lo.x && box_lo.x - reach <= hi.x && box_hi.y + reach >= lo.y && box_lo.y - reach <= hi.y)) {
    return;
  }
  // Near the plot but beyond float range (a huge radius, or one vertex far away): not drawn.
  if (!std::isfinite(radius)) return;
  for (const Vec2 p : mapped) {
    if (!is_finite(p)) return;
  }

  switch (item.kind) {
    case Kind::polygon:
      sink.polygon(mapped, radius, item.role);
      break;
    case Kind::circle:
      sink.circle(mapped[0], radius, item.role);
      break;
    case Kind::capsule:
      sink.capsule(mapped[0], mapped[1], radius, item.role);
      break;
    case Kind::segment:
    case Kind::arrow:
      break;  // above
    case Kind::point:
      sink.point(mapped[0], item.role);
      break;
    case Kind::label:
      sink.label(mapped[0] + Vec2{static_cast<float>(kLabelOffset), -static_cast<float>(kLabelOffset)},
                 texts_[item.text], item.role);
      break;
  }
}

void Picture::replay(PixelSink& sink) const {
  const PictureLayout lay = layout();
  std::vector<Vec2> scratch;  // one item's points in pixels, reused
  sink.begin(lay);
  for (size_t i = 0; i < lay.panels.size(); ++i) {
    const PanelView& view = lay.panels[i];
    sink.begin_panel(view);
    if (i < panels_.size()) {
      for (const Item& item : panels_[i].items) replay_item(item, view, sink, scratch);
    }
    sink.end_panel();
  }
  if (!lay.legend.empty()) {
    sink.begin_legend();
    for (const LegendEntry& e : lay.legend) {
      const DrawStyle& style = draw_style(e.role);
      const float x0 = static_cast<float>(e.swatch.x), y0 = static_cast<float>(e.swatch.y);
      const float x1 = x0 + static_cast<float>(e.swatch.width), y1 = y0 + static_cast<float>(e.swatch.height);
      const Vec2 mid{0.5f * (x0 + x1), 0.5f * (y0 + y1)};
      switch (style.swatch) {
        case Swatch::solid: {
          const std::array<Vec2, 4> square{Vec2{x0, y0}, Vec2{x1, y0}, Vec2{x1, y1}, Vec2{x0, y1}};
          sink.polygon(square, 0.0f, e.role);
          break;
        }
        case Swatch::line:
          sink.segment({x0, mid.y}, {x1, mid.y}, e.role);
          break;
        case Swatch::marker:
          sink.point(mid, e.role);
          break;
      }
      sink.text(e.text_origin, to_string(e.role));
    }
    sink.end_legend();
  }
  sink.end();
}

}  // namespace collide
