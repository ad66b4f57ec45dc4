#include <collide/core/debug_draw.hpp>

namespace collide {

const char* to_string(DrawRole role) noexcept {
  switch (role) {
    case DrawRole::static_geometry: return "static geometry";
    case DrawRole::sensor: return "sensor";
    case DrawRole::body: return "body";
    case DrawRole::fast_body: return "fast body";
    case DrawRole::contact_point: return "contact point";
    case DrawRole::contact_normal: return "contact normal";
    case DrawRole::laser: return "laser";
    case DrawRole::laser_hit: return "laser hit";
    case DrawRole::path: return "path";
    case DrawRole::shape_a: return "shape A";
    case DrawRole::shape_b: return "shape B";
    case DrawRole::minkowski: return "Minkowski difference";
    case DrawRole::origin: return "origin";
    case DrawRole::highlight: return "highlight";
  }
  return "unknown";
}

}  // namespace collide
