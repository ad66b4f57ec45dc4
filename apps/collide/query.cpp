// The JSON Lines query protocol, 2D and 3D. Parsing turns JSON into validated shapes through the
// shared JSON vocabulary (collide/io/shape_json.hpp: every rejection names its field), in the
// dimension the question's first telling member gives; then the library answers (3D pairs by
// its overloads, found at compile time, see "3D dispatch"); formatting writes floats with the
// fewest digits that round-trip. Reading is bounded (kMaxQueryLineBytes per line,
// kMaxJsonDepth, kMaxJsonHullPoints) and no exception leaves a line's handling.

#include "query.hpp"

#include <collide/broad/registry.hpp>
#include <collide/ccd/raycast.hpp>
#include <collide/ccd/shape_cast.hpp>
#include <collide/core/error.hpp>
#include <collide/io/shape_json.hpp>
#include <collide/narrow/closest_point.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/narrow/overlap.hpp>
#include <collide/shape/shape3d.hpp>
#include <collide/shape/triangle.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <concepts>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <istream>
#include <new>
#include <optional>
#include <ostream>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <variant>
#include <vector>

namespace collide::cli {
namespace {

using nlohmann::json;

/// A rejected question whose reason is not about one field (the message says it all).
struct QueryError {
  std::string message;
};

/// A float written with the fewest digits that read back as the same float. A result that is
/// not finite (JSON would print null) makes the whole answer an error: coordinates near the
/// float range (1e38) overflow the arithmetic of a query, in 2D and 3D alike.
json number(float v) {
  if (!std::isfinite(v)) {
    throw QueryError{"no finite answer: the result overflowed float arithmetic (coordinates or sizes too large)"};
  }
  if (v == 0.0f) v = 0.0f;  // print -0 as 0
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return json(std::strtod(std::string(buf, res.ptr).c_str(), nullptr));
}

json vec(Vec2 v) { return json::array({number(v.x), number(v.y)}); }
json vec(Vec3 v) { return json::array({number(v.x), number(v.y), number(v.z)}); }

// ---- the dimension of a question ---------------------------------------------------------------

/// What a member of a question holds, for telling its dimension.
enum class FieldKind : unsigned char { shape, transform, vector };

/// A member of a question that may tell the question's dimension.
struct Field {
  std::string_view key;
  FieldKind kind;
};

/// The dimension of a question and the field that told it.
struct Dimension {
  JsonDimension dimension = JsonDimension::two;
  /// Why, for messages: "told by a.center" (the telling member's path); "" when none told.
  std::string because;
};

const char* dimension_name(JsonDimension d) { return d == JsonDimension::three ? "3D" : "2D"; }

/// What `value`, a member of kind `kind`, tells of its dimension (a vector: 2 or 3 numbers).
std::optional<JsonDimensionCue> cue_of(const json& value, FieldKind kind) {
  switch (kind) {
    case FieldKind::shape:
      return shape_dimension_cue(value);
    case FieldKind::transform:
      return transform_dimension_cue(value);
    case FieldKind::vector:
      break;
  }
  if (value.is_array() && (value.size() == 2 || value.size() == 3)) {
    return JsonDimensionCue{value.size() == 3 ? JsonDimension::three : JsonDimension::two, ""};
  }
  return std::nullopt;
}

/// The dimension of question `q`: told by the first of `fields` that tells one (shapes first,
/// then transforms, then points and vectors: query-jsonl.md, "dimension is taken from the
/// coordinates"); 2D when none does (two spheres without centers and no transforms).
Dimension question_dimension(const json& q, const JsonPath& root, std::span<const Field> fields) {
  for (const Field& f : fields) {
    const json* value = find_member(q, f.key);
    if (value == nullptr) continue;
    if (const std::optional<JsonDimensionCue> cue = cue_of(*value, f.kind)) {
      const JsonPath member = root.member(f.key);
      return {cue->dimension, "told by " + (cue->field.empty() ? member.str() : member.member(cue->field).str())};
    }
  }
  return {};
}

/// Rejects `value` (a member of kind `kind` at `path`) when it tells a dimension other than the
/// question's, naming the member that tells it: "xa.q: a quaternion is a 3D rotation, in a 2D
/// question (told by a.center)".
void check_dimension(const json& value, FieldKind kind, const JsonPath& path, const Dimension& question) {
  const std::optional<JsonDimensionCue> cue = cue_of(value, kind);
  if (!cue || cue->dimension == question.dimension) return;
  const std::string in = std::string(", in a ") + dimension_name(question.dimension) + " question" +
                         (question.because.empty() ? std::string() : " (" + question.because + ")");
  const std::string_view field = cue->field;
  if (field.empty()) fail_json(path, std::string(dimension_name(cue->dimension)) + " coordinates" + in);
  const JsonPath where = path.member(field);
  if (field == "q") fail_json(where, "a quaternion is a 3D rotation" + in);
  if (field == "angle") fail_json(where, "an angle is a 2D rotation" + in);
  if (field == "type") {
    const std::string& type = value["type"].get_ref<const std::string&>();
    if (type == "circle") {
      fail_json(where, "a \"circle\" without center is 2D" + in + "; give it a 3-number center or call it \"sphere\"");
    }
    fail_json(where, json(type).dump() + " is a " + dimension_name(cue->dimension) + " shape" + in);
  }
  fail_json(where, std::string(dimension_name(cue->dimension)) + " coordinates" + in);
}

/// The shape in member `key` of question `q` (required), in the question's dimension; a
/// `sphere` without center takes it.
AnyShape shape_field(const json& q, const JsonPath& root, std::string_view key, const Dimension& dim) {
  const json& j = require_member(q, root, key);
  const JsonPath path = root.member(key);
  check_dimension(j, FieldKind::shape, path, dim);
  return shape_from_json(j, path, dim.dimension);
}

/// The 2D shape in member `key` of `q`, in a 2D question.
Shape2D shape2_field(const json& q, const JsonPath& root, std::string_view key, const Dimension& dim) {
  return std::get<Shape2D>(shape_field(q, root, key, dim));
}

/// The 2D transform in member `key` of `q`; omitted: the identity.
Transform transform_field(const json& q, const JsonPath& root, std::string_view key, const Dimension& dim) {
  const json* x = find_member(q, key);
  if (x == nullptr) return Transform{};
  check_dimension(*x, FieldKind::transform, root.member(key), dim);
  return transform_from_json(*x, root.member(key));
}

/// The 3D transform in member `key` of `q`; omitted: the identity.
Transform3 transform3_field(const json& q, const JsonPath& root, std::string_view key, const Dimension& dim) {
  const json* x = find_member(q, key);
  if (x == nullptr) return Transform3{};
  check_dimension(*x, FieldKind::transform, root.member(key), dim);
  return transform3_from_json(*x, root.member(key));
}

/// The 2D point or vector in member `key` of `q` (required).
Vec2 vec2_field(const json& q, const JsonPath& root, std::string_view key, const Dimension& dim) {
  const json& v = require_member(q, root, key);
  check_dimension(v, FieldKind::vector, root.member(key), dim);
  return vec2_from_json(v, root.member(key));
}

/// The 3D point or vector in member `key` of `q` (required).
Vec3 vec3_field(const json& q, const JsonPath& root, std::string_view key, const Dimension& dim) {
  const json& v = require_member(q, root, key);
  check_dimension(v, FieldKind::vector, root.member(key), dim);
  return vec3_from_json(v, root.member(key));
}

std::string feature_name(Feature f) {
  const char* kind = f.type == FeatureType::vertex ? "vertex"
                     : f.type == FeatureType::edge ? "edge"
                                                   : "face";
  return std::string(kind) + " " + std::to_string(f.index);
}

// ---- 3D dispatch ------------------------------------------------------------------------------
//
// A 3D question's shapes are the library's convex shapes (Shape3D) or triangles. Each op calls
// the library's overload for the pair of concrete types, found at compile time: a pair is
// answered as soon as the library declares its overload (in either order, the answer mirrored
// for the swapped one), and until then it is answered "unsupported pair", naming both shapes.
// Adding a pair to the library adds it here without a line.

/// Calls `f` with the concrete 3D shape `shape` holds.
template <class F>
decltype(auto) visit_3d(const AnyShape& shape, F&& f) {
  if (const auto* t = std::get_if<Triangle>(&shape)) return f(*t);
  return std::visit(f, std::get<Shape3D>(shape));
}

/// Calls `f` with the concrete 3D shapes `a` and `b` hold.
template <class F>
decltype(auto) visit_3d(const AnyShape& a, const AnyShape& b, F&& f) {
  return visit_3d(a, [&](const auto& sa) { return visit_3d(b, [&](const auto& sb) { return f(sa, sb); }); });
}

template <class A, class B>
concept HasOverlap3 = requires(const A& a, const B& b, const Transform3& x) {
  { overlap(a, x, b, x) } -> std::same_as<bool>;
};
template <class A, class B>
concept HasContact3 = requires(const A& a, const B& b, const Transform3& x) {
  { contact(a, x, b, x) } -> std::same_as<Manifold3>;
};
template <class A, class B>
concept HasDistance3 = requires(const A& a, const B& b, const Transform3& x) {
  { distance(a, x, b, x) } -> std::same_as<DistanceResult3>;
};
template <class A, class B>
concept HasShapeCast3 = requires(const A& a, const B& b, const Transform3& x, Vec3 v) {
  { shape_cast(a, x, v, b, x, v) } -> std::same_as<ShapeCastResult3>;
};
template <class S>
concept HasRaycast3 = requires(const S& s, const Transform3& x, const Ray3& r) {
  { raycast(s, x, r) } -> std::same_as<RayHit3>;
};
template <class S>
concept HasClosestPoint3 = requires(const S& s, const Transform3& x, Vec3 p) {
  { closest_point(s, x, p) } -> std::same_as<PointQuery3>;
};

[[noreturn]] void unsupported_pair(std::string_view op, const AnyShape& a, const AnyShape& b) {
  throw QueryError{"unsupported pair: the library has no " + std::string(op) + " for a " + type_name(a) +
                   " (a) and a " + type_name(b) + " (b) yet"};
}

[[noreturn]] void unsupported_shape(std::string_view op, const AnyShape& shape) {
  throw QueryError{"unsupported shape: the library has no " + std::string(op) + " for a " +
                   type_name(shape) + " (shape) yet"};
}

bool overlap_3d(const AnyShape& a, const Transform3& xa, const AnyShape& b, const Transform3& xb) {
  return visit_3d(a, b, [&]<class A, class B>(const A& sa, const B& sb) -> bool {
    if constexpr (HasOverlap3<A, B>) return overlap(sa, xa, sb, xb);
    else if constexpr (HasOverlap3<B, A>) return overlap(sb, xb, sa, xa);
    else unsupported_pair("overlap", a, b);
  });
}

Manifold3 contact_3d(const AnyShape& a, const Transform3& xa, const AnyShape& b, const Transform3& xb) {
  return visit_3d(a, b, [&]<class A, class B>(const A& sa, const B& sb) -> Manifold3 {
    if constexpr (HasContact3<A, B>) return contact(sa, xa, sb, xb);
    else if constexpr (HasContact3<B, A>) return reversed(contact(sb, xb, sa, xa));
    else unsupported_pair("contact", a, b);
  });
}

DistanceResult3 distance_3d(const AnyShape& a, const Transform3& xa, const AnyShape& b, const Transform3& xb) {
  return visit_3d(a, b, [&]<class A, class B>(const A& sa, const B& sb) -> DistanceResult3 {
    if constexpr (HasDistance3<A, B>) {
      return distance(sa, xa, sb, xb);
    } else if constexpr (HasDistance3<B, A>) {
      DistanceResult3 d = distance(sb, xb, sa, xa);
      std::swap(d.point_a, d.point_b);
      d.normal = -d.normal;
      return d;
    } else {
      unsupported_pair("distance", a, b);
    }
  });
}

ShapeCastResult3 shape_cast_3d(const AnyShape& a, const Transform3& xa, Vec3 va, const AnyShape& b,
                               const Transform3& xb, Vec3 vb) {
  return visit_3d(a, b, [&]<class A, class B>(const A& sa, const B& sb) -> ShapeCastResult3 {
    if constexpr (HasShapeCast3<A, B>) {
      return shape_cast(sa, xa, va, sb, xb, vb);
    } else if constexpr (HasShapeCast3<B, A>) {
      ShapeCastResult3 r = shape_cast(sb, xb, vb, sa, xa, va);
      r.normal = -r.normal;
      return r;
    } else {
      unsupported_pair("toi", a, b);
    }
  });
}

RayHit3 raycast_3d(const AnyShape& shape, const Transform3& x, const Ray3& ray) {
  return visit_3d(shape, [&]<class S>(const S& s) -> RayHit3 {
    if constexpr (HasRaycast3<S>) return raycast(s, x, ray);
    else unsupported_shape("raycast", shape);
  });
}

PointQuery3 closest_point_3d(const AnyShape& shape, const Transform3& x, Vec3 point) {
  return visit_3d(shape, [&]<class S>(const S& s) -> PointQuery3 {
    if constexpr (HasClosestPoint3<S>) return closest_point(s, x, point);
    else unsupported_shape("closest_point", shape);
  });
}

/// The `boxes` of a `pairs` question: each [minx, miny, maxx, maxy] (2D) or
/// [minx, miny, minz, maxx, maxy, maxz] (3D), one dimension for all.
json answer_pairs(const json& q, const JsonPath& root) {
  const JsonPath boxes_path = root.member("boxes");
  const json& boxes = require_member(q, root, "boxes");
  if (!boxes.is_array()) fail_json(boxes_path, "expected an array of boxes, got " + json_kind(boxes));
  std::string name;
  if (const json* b = find_member(q, "broadphase")) name = string_from_json(*b, root.member("broadphase"));
  const size_t width = boxes.empty() || !boxes[0].is_array() ? 4 : boxes[0].size();
  if (width != 4 && width != 6) fail_json(boxes_path.element(0), "expected 4 (2D) or 6 (3D) numbers");
  std::vector<Aabb> boxes2;
  std::vector<Aabb3> boxes3;
  for (size_t i = 0; i < boxes.size(); ++i) {
    const JsonPath field = boxes_path.element(i);
    const json& b = boxes[i];
    if (!b.is_array() || b.size() != width) {
      fail_json(field, "expected " + std::to_string(width) + " numbers like boxes[0]");
    }
    float v[6];
    for (size_t k = 0; k < width; ++k) v[k] = float_from_json(b[k], field.element(k));
    if (width == 4) {
      boxes2.push_back({{v[0], v[1]}, {v[2], v[3]}});
    } else {
      boxes3.push_back({{v[0], v[1], v[2]}, {v[3], v[4], v[5]}});
    }
  }
  PairList pairs;
  try {
    pairs = width == 4 ? find_pairs(name, boxes2) : find_pairs(name, boxes3);
  } catch (const InvalidInput& e) {
    // A bad box is "box 3: ...", said of "boxes"; the other messages ("broadphase: unknown
    // name ...") name their field already.
    const std::string why = e.what();
    if (why.rfind("box ", 0) == 0) throw JsonFieldError("boxes", why);
    throw QueryError{why};
  }
  json out = json::array();
  for (const auto& [i, j] : pairs) out.push_back(json::array({i, j}));
  return json::object({{"pairs", out}});
}

/// The fields of a question about two shapes, in the order that tells its dimension.
constexpr Field kPairFields[] = {
    {"a", FieldKind::shape},      {"b", FieldKind::shape},      {"xa", FieldKind::transform},
    {"xb", FieldKind::transform}, {"va", FieldKind::vector},    {"vb", FieldKind::vector}};

/// The fields of a 2D `toi` question; a field telling 3D is rejected, naming it.
CastQuestion to_cast_question(const json& q, const JsonPath& root, const Dimension& dim) {
  CastQuestion c;
  c.a = shape2_field(q, root, "a", dim);
  c.b = shape2_field(q, root, "b", dim);
  c.xa = transform_field(q, root, "xa", dim);
  c.xb = transform_field(q, root, "xb", dim);
  c.va = vec2_field(q, root, "va", dim);
  c.vb = vec2_field(q, root, "vb", dim);
  return c;
}

json features(const ContactId& id) {
  return json::array({feature_name(id.feature_a()), feature_name(id.feature_b())});
}

/// The answer fields of a `contact` question (2D: no `features`, as before 3D existed).
template <int D>
void write_contact(const ManifoldN<D>& m, json& out) {
  out["touching"] = m.touching();
  if (!m.touching()) return;
  out["normal"] = vec(m.normal);
  out["depth"] = number(m.max_depth());
  json points = json::array();
  json depths = json::array();
  json ids = json::array();
  for (int i = 0; i < m.count; ++i) {
    points.push_back(vec(m.points[i].point));
    depths.push_back(number(m.points[i].depth));
    if constexpr (D == 3) ids.push_back(features(m.points[i].id));
  }
  out["points"] = points;
  out["depths"] = depths;
  if constexpr (D == 3) out["features"] = ids;
}

template <int D>
void write_distance(const DistanceResultN<D>& d, json& out) {
  out["distance"] = number(d.distance);
  out["pa"] = vec(d.point_a);
  out["pb"] = vec(d.point_b);
}

template <int D>
void write_raycast(const RayHitN<D>& hit, json& out) {
  out["hit"] = hit.hit;
  if (!hit.hit) return;
  out["fraction"] = number(hit.fraction);
  out["point"] = vec(hit.point);
  out["normal"] = vec(hit.normal);
}

template <int D>
void write_closest_point(const PointQueryN<D>& r, json& out) {
  out["inside"] = r.inside;
  out["distance"] = number(r.distance);
  out["closest"] = vec(r.closest);
  out["feature"] = feature_name(r.feature);
}

/// The answer fields of a `toi` question, from a shape cast; an iteration cap is an error.
template <int D>
void write_toi(const ShapeCastResultN<D>& r, json& out) {
  if (r.status == QueryStatus::max_iterations) {
    throw QueryError{"time of impact did not converge (iteration cap); no contact before t = " +
                     std::to_string(r.fraction)};
  }
  out["hit"] = r.hit;
  if (!r.hit) return;
  out["t"] = number(r.fraction);
  out["point"] = vec(r.point);
  out["normal"] = vec(r.normal);
}

/// overlap, contact, distance: two shapes A and B placed by xa and xb.
json answer_pair(const json& q, const JsonPath& root, const std::string& op) {
  const Dimension dim = question_dimension(q, root, kPairFields);
  json out;
  if (dim.dimension == JsonDimension::two) {
    const Shape2D a = shape2_field(q, root, "a", dim);
    const Shape2D b = shape2_field(q, root, "b", dim);
    const Transform xa = transform_field(q, root, "xa", dim);
    const Transform xb = transform_field(q, root, "xb", dim);
    if (op == "overlap") out["overlap"] = overlap(a, xa, b, xb);
    else if (op == "contact") write_contact(contact(a, xa, b, xb), out);
    else write_distance(distance(a, xa, b, xb), out);
    return out;
  }
  const AnyShape a = shape_field(q, root, "a", dim);
  const AnyShape b = shape_field(q, root, "b", dim);
  const Transform3 xa = transform3_field(q, root, "xa", dim);
  const Transform3 xb = transform3_field(q, root, "xb", dim);
  if (op == "overlap") out["overlap"] = overlap_3d(a, xa, b, xb);
  else if (op == "contact") write_contact(contact_3d(a, xa, b, xb), out);
  else write_distance(distance_3d(a, xa, b, xb), out);
  return out;
}

/// raycast, closest_point: one shape placed by x, and a ray or a point.
json answer_single(const json& q, const JsonPath& root, const std::string& op) {
  static constexpr Field kRayFields[] = {{"shape", FieldKind::shape},
                                         {"x", FieldKind::transform},
                                         {"origin", FieldKind::vector},
                                         {"translation", FieldKind::vector}};
  static constexpr Field kPointFields[] = {
      {"shape", FieldKind::shape}, {"x", FieldKind::transform}, {"point", FieldKind::vector}};
  const bool ray = op == "raycast";
  const Dimension dim = ray ? question_dimension(q, root, kRayFields) : question_dimension(q, root, kPointFields);
  json out;
  if (dim.dimension == JsonDimension::two) {
    const Shape2D shape = shape2_field(q, root, "shape", dim);
    const Transform x = transform_field(q, root, "x", dim);
    if (ray) {
      const Ray r{vec2_field(q, root, "origin", dim), vec2_field(q, root, "translation", dim)};
      write_raycast(raycast(shape, x, r), out);
    } else {
      write_closest_point(closest_point(shape, x, vec2_field(q, root, "point", dim)), out);
    }
    return out;
  }
  const AnyShape shape = shape_field(q, root, "shape", dim);
  const Transform3 x = transform3_field(q, root, "x", dim);
  if (ray) {
    const Ray3 r{vec3_field(q, root, "origin", dim), vec3_field(q, root, "translation", dim)};
    write_raycast(raycast_3d(shape, x, r), out);
  } else {
    write_closest_point(closest_point_3d(shape, x, vec3_field(q, root, "point", dim)), out);
  }
  return out;
}

/// toi: A and B placed by xa and xb, translating by va and vb over t in [0, 1].
json answer_toi(const json& q, const JsonPath& root) {
  const Dimension dim = question_dimension(q, root, kPairFields);
  json out;
  try {
    if (dim.dimension == JsonDimension::two) {
      const CastQuestion c = to_cast_question(q, root, dim);
      write_toi(shape_cast(c.a, c.xa, c.va, c.b, c.xb, c.vb), out);
    } else {
      const AnyShape a = shape_field(q, root, "a", dim);
      const AnyShape b = shape_field(q, root, "b", dim);
      const Transform3 xa = transform3_field(q, root, "xa", dim);
      const Transform3 xb = transform3_field(q, root, "xb", dim);
      const Vec3 va = vec3_field(q, root, "va", dim);
      const Vec3 vb = vec3_field(q, root, "vb", dim);
      write_toi(shape_cast_3d(a, xa, va, b, xb, vb), out);
    }
  } catch (const JsonFieldError&) {
    throw;
  } catch (const InvalidInput& e) {  // the library's own check of the motion
    throw QueryError{e.what()};
  }
  return out;
}

json answer(const json& q) {
  const JsonPath root;
  check_object(q, root, "a question");
  const std::string& op = string_from_json(require_member(q, root, "op"), root.member("op"));
  if (op == "overlap" || op == "contact" || op == "distance") return answer_pair(q, root, op);
  if (op == "raycast" || op == "closest_point") return answer_single(q, root, op);
  if (op == "pairs") return answer_pairs(q, root);
  if (op == "toi") return answer_toi(q, root);
  fail_json(root.member("op"), "unknown op " + json(op).dump());  // quoted and escaped
}

}  // namespace

std::string answer_query_line(std::string_view line) {
  if (line.find_first_not_of(" \t\r\n") == std::string_view::npos) return {};
  try {
    json id = nullptr;
    json out;
    try {
      const json q = parse_json(line);  // depth-limited; 1e400 kept for its field to be named
      if (const json* i = find_member(q, "id")) id = *i;
      out = answer(q);
    } catch (const InvalidInput& e) {  // a field named by the JSON vocabulary or the library
      out = json::object({{"error", e.what()}});
    } catch (const QueryError& e) {
      out = json::object({{"error", e.message}});
    } catch (const std::bad_alloc&) {
      out = json::object({{"error", "out of memory while answering this line"}});
    } catch (const std::exception& e) {
      out = json::object({{"error", std::string("internal error: ") + e.what()}});
    }
    json result = json::object({{"id", id}});
    result.update(out);
    // Every string came from parsed (so valid) UTF-8 or from messages made valid; replacing
    // any bad byte anyway keeps the answer valid JSON whatever a message might hold.
    return result.dump(-1, ' ', false, json::error_handler_t::replace);
  } catch (...) {  // not even the error answer could be made (out of memory)
    return R"({"id":null,"error":"internal error: no answer could be written for this line"})";
  }
}

CastQuestion parse_cast_question(std::string_view text) {
  try {
    const JsonPath root;
    const json q = parse_json(text);
    check_object(q, root, "a question");
    if (const json* op = find_member(q, "op"); op != nullptr && *op != "toi") {
      fail_json(root.member("op"), "a cast question is a \"toi\" question");
    }
    return to_cast_question(q, root, Dimension{JsonDimension::two, "collide cast draws 2D questions only"});
  } catch (const QueryError& e) {
    throw InvalidInput(e.message);
  }
}

namespace {

enum class LineRead : unsigned char { line, too_long, end };

/// Reads the next line of `in` (without its '\n') into `line`, keeping at most
/// kMaxQueryLineBytes bytes: a longer line is read to its end but not kept (too_long), so no
/// line makes the buffer grow beyond the limit. A read error sets badbit and ends the input.
LineRead read_line(std::istream& in, std::string& line) {
  line.clear();
  std::streambuf* buf = in.rdbuf();
  if (!in.good() || buf == nullptr) return LineRead::end;
  const auto next = [&]() -> int {
    try {
      return buf->sbumpc();
    } catch (...) {  // libstdc++'s filebuf throws on a read error (EISDIR on a folder)
      if (in.exceptions() & std::ios::badbit) throw;  // as the stream's own reads do
      in.setstate(std::ios::badbit);
      return std::char_traits<char>::eof();
    }
  };
  bool any = false;
  bool too_long = false;
  for (;;) {
    const int c = next();
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      if (!any || in.bad()) return LineRead::end;
      break;
    }
    any = true;
    if (c == '\n') break;
    if (too_long) continue;
    if (line.size() == kMaxQueryLineBytes) {
      too_long = true;
      continue;
    }
    if (line.size() == line.capacity()) line.reserve(std::min(kMaxQueryLineBytes, std::max<std::size_t>(256, 2 * line.size())));
    line.push_back(static_cast<char>(c));
  }
  return too_long ? LineRead::too_long : LineRead::line;
}

}  // namespace

std::size_t answer_query_stream(std::istream& in, std::ostream& out) {
  std::size_t answered = 0;
  std::size_t number = 0;
  std::string line;
  for (LineRead r; (r = read_line(in, line)) != LineRead::end;) {
    ++number;
    std::string reply;
    if (r == LineRead::too_long) {
      reply = json::object({{"id", nullptr},
                            {"error", "line " + std::to_string(number) + ": longer than " +
                                          std::to_string(kMaxQueryLineBytes) +
                                          " bytes (the limit, 16 MiB); not read"}})
                  .dump();
    } else {
      reply = answer_query_line(line);
    }
    if (reply.empty()) continue;
    out << reply << '\n';
    ++answered;
  }
  out.flush();
  if (in.bad()) throw std::runtime_error("read error after line " + std::to_string(number));
  return answered;
}

int run_query(const std::string& file, std::istream& standard_input, std::ostream& out, std::ostream& err) {
  const bool from_stdin = file.empty() || file == "-";
  const std::string name = from_stdin ? std::string("standard input") : file;
  try {
    if (from_stdin) {
      answer_query_stream(standard_input, out);
    } else {
      std::error_code ec;
      if (std::filesystem::is_directory(file, ec)) {
        err << "collide query: " << name << ": cannot be read (a directory)\n";
        return 2;
      }
      std::ifstream in(file, std::ios::binary);
      if (!in) {
        err << "collide query: " << name << ": cannot be read\n";
        return 2;
      }
      answer_query_stream(in, out);
    }
    if (!out) {
      err << "collide query: the answers could not be written\n";
      return 2;
    }
    return 0;
  } catch (const std::bad_alloc&) {
    err << "collide query: " << name << ": out of memory\n";
  } catch (const std::exception& e) {
    err << "collide query: " << name << ": " << e.what() << "\n";
  } catch (...) {
    err << "collide query: " << name << ": unknown error\n";
  }
  return 2;
}

std::string query_ops_help() {
  std::string text =
      std::string("Ops (one JSON object per line; every answer echoes \"id\"):\n"
      "  overlap        a, xa, b, xb                 -> overlap\n"
      "  contact        a, xa, b, xb                 -> touching, normal (A to B), depth, points, depths\n"
      "  distance       a, xa, b, xb                 -> distance, pa, pb\n"
      "  raycast        shape, x, origin, translation -> hit, fraction, point, normal\n"
      "  closest_point  shape, x, point               -> inside, distance (signed), closest, feature\n"
      "  toi            a, xa, va, b, xb, vb          -> hit, t (first touch in [0, 1]), point, normal\n"
      "  pairs          boxes, broadphase?            -> pairs ([i, j], i < j, sorted, each once)\n"
      "Shapes: circle {center, radius}, capsule {a, b, radius}, box {half, radius?},\n"
      "        polygon {vertices (convex, counter-clockwise), radius?}, segment {a, b}\n"
      "  3D (3 numbers per point): sphere {center, radius}, capsule, box, segment as above,\n"
      "        hull {points (4 to ") + std::to_string(kMaxJsonHullPoints) + "; their convex hull), radius?},\n"
      "        triangle {vertices (3)}\n"
      "Transforms: 2D {\"p\": [x, y], \"angle\": radians}; 3D {\"p\": [x, y, z], \"q\": [w, x, y, z]}\n"
      "        (unit quaternion within 1e-3); omitted means identity.\n"
      "A question is 2D or 3D as its first shape, transform or point tells; 3D contact answers\n"
      "also give \"features\" ([A's, B's] per point). Shapes and transforms take only these\n"
      "fields (and \"comment\").\n"
      "Limits: 16 MiB per line, JSON nested at most 256 deep (docs/shape-json.md).\n"
      "Boxes: [minx, miny, maxx, maxy] (2D) or [minx, miny, minz, maxx, maxy, maxz] (3D).\n"
      "Broad phases (\"broadphase\"; the first is the default):\n";
  for (const BroadPhaseInfo& info : broadphases()) {
    const std::string name(info.name);
    text += "  " + name + std::string(name.size() < 18 ? 18 - name.size() : 1, ' ') +
            std::string(info.description) + "\n";
  }
  return text;
}

}  // namespace collide::cli
