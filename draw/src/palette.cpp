#include <collide/draw/palette.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace collide {
namespace {

constexpr Color rgb(std::uint8_t r, std::uint8_t g, std::uint8_t b, std::uint8_t a = 255) {
  return {r, g, b, a};
}
constexpr Color kNone{0, 0, 0, 0};

// Indexed by DrawRole. Translucent fills where shapes are expected to overlap (sensors, the two
// shapes of a query, the Minkowski difference, highlights), opaque where they stand alone.
constexpr std::array<DrawStyle, kDrawRoleCount> kStyles = {{
    // static_geometry
    {rgb(190, 190, 190), rgb(100, 100, 100), 1.5f, 3.0f, PointMarker::dot, Swatch::solid, false},
    // sensor
    {rgb(70, 200, 200, 60), rgb(20, 150, 150), 1.5f, 3.0f, PointMarker::dot, Swatch::solid, true},
    // body
    {rgb(110, 160, 235, 220), rgb(30, 80, 170), 1.5f, 3.0f, PointMarker::dot, Swatch::solid, false},
    // fast_body
    {rgb(255, 150, 40, 230), rgb(200, 80, 0), 1.5f, 3.0f, PointMarker::dot, Swatch::solid, false},
    // contact_point
    {rgb(0, 0, 0), rgb(0, 0, 0), 1.0f, 3.5f, PointMarker::dot, Swatch::marker, false},
    // contact_normal
    {rgb(60, 60, 60), rgb(60, 60, 60), 1.5f, 3.0f, PointMarker::dot, Swatch::line, false},
    // laser
    {rgb(255, 20, 20), rgb(255, 20, 20), 1.25f, 3.0f, PointMarker::dot, Swatch::line, false},
    // laser_hit
    {rgb(220, 0, 0), rgb(220, 0, 0), 1.0f, 3.5f, PointMarker::dot, Swatch::marker, false},
    // path
    {kNone, rgb(120, 120, 140), 1.0f, 2.5f, PointMarker::dot, Swatch::line, true},
    // shape_a
    {rgb(70, 130, 230, 110), rgb(30, 80, 190), 2.0f, 3.5f, PointMarker::dot, Swatch::solid, false},
    // shape_b
    {rgb(60, 180, 90, 110), rgb(20, 120, 50), 2.0f, 3.5f, PointMarker::dot, Swatch::solid, false},
    // minkowski
    {rgb(150, 90, 210, 60), rgb(120, 60, 180), 1.5f, 3.0f, PointMarker::dot, Swatch::solid, false},
    // origin
    {rgb(0, 0, 0), rgb(0, 0, 0), 1.5f, 6.0f, PointMarker::cross, Swatch::marker, false},
    // highlight
    {rgb(235, 50, 210, 90), rgb(200, 0, 170), 2.5f, 4.5f, PointMarker::dot, Swatch::solid, false},
}};

}  // namespace

Color distinct_color(int index) noexcept {
  // Hue: index times the golden angle (360 / phi^2 degrees), as a fraction of a turn.
  constexpr double kGoldenTurn = 0.3819660112501051;
  constexpr std::array<double, 3> kSaturation{0.62, 0.45, 0.75};
  constexpr std::array<double, 3> kValue{0.92, 0.80, 0.70};
  const double turns = static_cast<double>(index) * kGoldenTurn;
  const double h = 6.0 * (turns - std::floor(turns));  // [0, 6): the sector of the colour wheel
  const auto cycle = static_cast<std::size_t>(((index % 9) + 9) % 9);
  const double s = kSaturation[cycle % 3], v = kValue[cycle / 3];
  // HSV to RGB (Smith 1978): the largest channel v, the smallest v (1 - s), the middle one
  // moving between them across the sector.
  const double f = h - std::floor(h);
  const double p = v * (1.0 - s), q = v * (1.0 - s * f), t = v * (1.0 - s * (1.0 - f));
  double r = v, g = t, b = p;
  switch (static_cast<int>(h)) {
    case 0: r = v, g = t, b = p; break;
    case 1: r = q, g = v, b = p; break;
    case 2: r = p, g = v, b = t; break;
    case 3: r = p, g = q, b = v; break;
    case 4: r = t, g = p, b = v; break;
    default: r = v, g = p, b = q; break;
  }
  const auto channel = [](double x) { return static_cast<std::uint8_t>(std::clamp(x * 255.0 + 0.5, 0.0, 255.0)); };
  return {channel(r), channel(g), channel(b), 255};
}

const DrawStyle& draw_style(DrawRole role) noexcept {
  const auto i = static_cast<unsigned>(role);
  return kStyles[i < kStyles.size() ? i : 0];
}

}  // namespace collide
