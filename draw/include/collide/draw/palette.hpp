#pragma once
/// @file
/// The one palette of debug pictures: each DrawRole has one style, used for every picture
/// (PNG, SVG or PDF: cairo_picture.hpp), so a colour means the same thing in every picture and
/// the legend can name it. Sizes are in image pixels, independent of the world scale.
///
/// The choice, so a picture reads at a glance on a white background: static geometry grey,
/// sensors translucent teal, bodies blue, fast bodies orange, contact points black dots with
/// dark grey normal arrows, lasers thin bright red with red hit dots, paths thin dashed grey,
/// shape A blue and shape B green (translucent, so overlaps show), the Minkowski difference
/// translucent purple, the origin a black cross, highlights magenta.

#include <collide/core/debug_draw.hpp>

#include <cstdint>

namespace collide {

/// An 8-bit RGBA colour, not premultiplied; a = 255 is opaque.
struct Color {
  std::uint8_t r = 0, g = 0, b = 0, a = 255;
  friend constexpr bool operator==(Color, Color) noexcept = default;
};

/// How a point (draw_point) of a role is marked.
enum class PointMarker : unsigned char {
  dot,    ///< a disc of `point_size` radius
  cross,  ///< an upright cross of `point_size` half-length, stroked
};

/// What the legend shows for a role.
enum class Swatch : unsigned char {
  solid,   ///< a small filled and outlined square (roles drawn mostly as shapes)
  line,    ///< a short stroke (segments, rays, arrows, paths)
  marker,  ///< the point marker (contact points, hits, the origin)
};

/// The look of one role. Solids are filled with `fill` (alpha 0: not filled) and outlined with
/// `stroke`; everything else (segments, arrows, points, label text) is drawn in `stroke`.
struct DrawStyle {
  Color fill;                            ///< interior of solids
  Color stroke;                          ///< outlines, lines, arrows, points, label text
  float stroke_width = 1.0f;             ///< pixels
  float point_size = 3.0f;               ///< dot radius or cross half-length, pixels
  PointMarker marker = PointMarker::dot;
  Swatch swatch = Swatch::solid;
  bool dashed = false;                   ///< dashed lines, arrow shafts and outlines of solids
};

/// The style of `role`. Roles outside the enum get the static-geometry style.
[[nodiscard]] const DrawStyle& draw_style(DrawRole role) noexcept;

/// The `index`-th of a sequence of colours told apart by number, not by role (the hulls of a
/// decomposition, islands): opaque, mid-light, hues a golden angle apart, so colours close in
/// index are far apart in hue (consecutive ones more than 100 apart in 8-bit RGB), with
/// saturation and brightness cycling over 3 steps each; indices 0 to 1023 give 1024 different
/// colours. Any index, negative ones too.
[[nodiscard]] Color distinct_color(int index) noexcept;

/// Background of every picture.
inline constexpr Color kPictureBackground{255, 255, 255, 255};
/// Titles and legend text.
inline constexpr Color kPictureText{30, 30, 30, 255};
/// The thin frame around each panel's plot area.
inline constexpr Color kPanelFrame{200, 200, 205, 255};

/// Length of the head of every arrow, pixels (shorter arrows get a head of half their length).
inline constexpr float kArrowHeadLength = 9.0f;
/// Half of the width of an arrow head at its base, pixels.
inline constexpr float kArrowHeadHalfWidth = 4.0f;
/// Dash and gap length of dashed strokes, pixels.
inline constexpr float kDashLength = 5.0f;
/// Width of the frame around each panel's plot area, pixels.
inline constexpr float kPanelFrameWidth = 1.0f;
/// Width of the background-coloured outline behind label text, so a label reads over shapes,
/// pixels (half of it reaches beyond the glyphs).
inline constexpr float kLabelHaloWidth = 3.0f;

}  // namespace collide
