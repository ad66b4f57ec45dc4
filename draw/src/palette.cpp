#include <collide/draw/palette.hpp>

#include <array>

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

const DrawStyle& draw_style(DrawRole role) noexcept {
  const auto i = static_cast<unsigned>(role);
  return kStyles[i < kStyles.size() ? i : 0];
}

}  // namespace collide
