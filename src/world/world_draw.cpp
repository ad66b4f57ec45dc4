// The world drawn through the debug-draw interface of its dimension (DebugDraw, DebugDraw3):
// statics, bodies, contacts, lasers.

#include "world_impl.hpp"

#include <collide/world/world2d.hpp>
#include <collide/world/world3d.hpp>

#include <collide/shape/draw_shape.hpp>

#include <algorithm>
#include <memory>
#include <type_traits>
#include <variant>
#include <vector>

namespace collide {

template <int D>
void WorldN<D>::draw(DebugDrawN<D>& draw, const WorldDrawOptions& options) const {
  const Impl& w = *impl_;
  if (options.statics) {
    for (const StaticDefN<D>& st : w.statics) {
      const DrawRole role = st.sensor ? DrawRole::sensor : DrawRole::static_geometry;
      for (const StaticShape& s : st.shapes) {
        if constexpr (D == 2) {
          draw_shape(draw, s, st.transform, role);
        } else {
          std::visit(
              [&](const auto& shape) {
                using S = std::decay_t<decltype(shape)>;
                if constexpr (detail::kIsMesh<S> || detail::kIsField<S>) {
                  if (shape != nullptr) draw_shape(draw, *shape, st.transform, role);
                } else {
                  draw_shape(draw, Shape3D(shape), st.transform, role);
                }
              },
              s);
        }
      }
      for (const StaticFieldN<D>& f : st.fields) detail::draw_field<D>(draw, f, st.transform, role);
    }
  }
  std::vector<float> sizes;
  if (options.bodies) {
    for (const detail::BodyN<D>& b : w.bodies) {
      if (!b.alive) continue;
      const DrawRole role = b.sensor                  ? DrawRole::sensor
                            : b.bullet || b.very_fast ? DrawRole::fast_body
                                                      : DrawRole::body;
      for (const BodyShape& s : b.shapes) draw_shape(draw, s, b.xf, role);
      sizes.push_back(b.bounding_radius);
    }
  }
  if (options.contacts) {
    float length = options.normal_length;
    if (length <= 0.0f) {
      if (!sizes.empty()) {
        std::nth_element(sizes.begin(), sizes.begin() + static_cast<std::ptrdiff_t>(sizes.size() / 2), sizes.end());
        length = sizes[sizes.size() / 2];
      } else {
        length = 1.0f;
      }
    }
    for (const ContactN<D>& c : w.previous_contacts) {
      const ManifoldN<D>& m = c.manifold;
      Vec mid(0.0f);
      for (int i = 0; i < m.count; ++i) {
        draw.draw_point(m.points[i].point, DrawRole::contact_point);
        mid += m.points[i].point;
      }
      if (m.count > 0) {
        mid /= static_cast<float>(m.count);
        draw.draw_arrow(mid, mid + length * m.normal, DrawRole::contact_normal);
      }
    }
  }
}

template <int D>
void WorldN<D>::draw_laser(DebugDrawN<D>& draw, const LaserPathN<D>& path) {
  for (int i = 0; i < path.segments; ++i) {
    draw.draw_segment(path.points[i], path.points[i + 1], DrawRole::laser);
  }
  for (int i = 0; i < path.hit_count; ++i) draw.draw_point(path.hits[i].hit.point, DrawRole::laser_hit);
}

template void WorldN<2>::draw(DebugDraw&, const WorldDrawOptions&) const;
template void WorldN<2>::draw_laser(DebugDraw&, const LaserPathN<2>&);
template void WorldN<3>::draw(DebugDraw3&, const WorldDrawOptions&) const;
template void WorldN<3>::draw_laser(DebugDraw3&, const LaserPathN<3>&);

}  // namespace collide
