// The JSON vocabulary of shapes and transforms (docs/shape-json.md): reading JSON text safely,
// naming every rejected value by its path, and turning shape and transform objects into
// validated library types. `collide query` and scene files both read through here.

#include <collide/io/shape_json.hpp>

#include "json_syntax.hpp"
#include "text_file.hpp"

#include <collide/shape/convex_hull.hpp>
#include <collide/world/world2d.hpp>  // convex_pieces

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>

namespace collide {
namespace {

using Json = nlohmann::json;

// ---- JSON text ---------------------------------------------------------------------------------

/// A number beyond double range (1e400) fails nlohmann's parsing before any field is known. Such
/// a document is parsed again with each of those numbers turned into a string starting with this
/// mark (a control character, so no string a user types): the readers below then name the field.
constexpr std::string_view kBeyondDouble = "\x01" "beyond double range: ";

bool beyond_double(const Json& j) {
  return j.is_string() && j.get_ref<const std::string&>().starts_with(kBeyondDouble);
}

/// The number a kBeyondDouble string stands for, as written ("1e400").
std::string_view beyond_double_token(const Json& j) {
  return std::string_view(j.get_ref<const std::string&>()).substr(kBeyondDouble.size());
}

/// `text` with every number beyond double range written as a kBeyondDouble string, and where
/// each such string ends in both texts, so positions in the result map back to `text`.
struct MarkedText {
  struct Shift {
    std::size_t marked_begin, marked_end;  ///< the inserted string, in `text`
    std::size_t source_begin, source_end;  ///< the number it replaces, in the source
  };
  std::string text;
  std::vector<Shift> shifts;

  /// The source offset of offset `at` in `text`: inside a replaced number, its start.
  [[nodiscard]] std::size_t source_offset(std::size_t at) const {
    std::size_t delta_marked = 0, delta_source = 0;
    for (const Shift& s : shifts) {
      if (at < s.marked_begin) break;
      if (at < s.marked_end) return s.source_begin;
      delta_marked = s.marked_end;
      delta_source = s.source_end;
    }
    return at - delta_marked + delta_source;
  }
};

/// Length of the number JSON's grammar reads at the start of `text` (RFC 8259, section 6:
/// -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?), as nlohmann's lexer takes it: the longest
/// prefix that is a number ("1e400" of "1e400.5"); 0 when there is none ("-x").
std::size_t json_number_length(std::string_view text) {
  std::size_t i = 0;
  const auto digits = [&](std::size_t from) {
    while (from < text.size() && text[from] >= '0' && text[from] <= '9') ++from;
    return from;
  };
  if (i < text.size() && text[i] == '-') ++i;
  if (i < text.size() && text[i] == '0') {
    ++i;
  } else if (i < text.size() && text[i] >= '1' && text[i] <= '9') {
    i = digits(i);
  } else {
    return 0;
  }
  if (i + 1 < text.size() && text[i] == '.' && text[i + 1] >= '0' && text[i + 1] <= '9') i = digits(i + 1);
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    std::size_t k = i + 1;
    if (k < text.size() && (text[k] == '+' || text[k] == '-')) ++k;
    if (k < text.size() && text[k] >= '0' && text[k] <= '9') i = digits(k);
  }
  return i;
}

/// Strings are copied as they are: a run of digits inside one is not a number. Numbers are cut
/// where nlohmann's lexer cuts them, so what follows a marked number ("1e400.5") is still read
/// (and rejected) as it was.
MarkedText mark_numbers_beyond_double(std::string_view source) {
  MarkedText out;
  out.text.reserve(source.size() + 64);
  bool in_string = false;
  for (std::size_t i = 0; i < source.size();) {
    const char c = source[i];
    if (in_string) {
      if (c == '\\' && i + 1 < source.size()) out.text += source[i++];  // the escaped char follows
      else if (c == '"') in_string = false;
      out.text += source[i++];
    } else if (c == '"') {
      in_string = true;
      out.text += source[i++];
    } else if (const std::size_t length = c == '-' || (c >= '0' && c <= '9') ? json_number_length(source.substr(i)) : 0;
               length > 0) {
      const std::string token(source.substr(i, length));
      if (std::isinf(std::strtod(token.c_str(), nullptr))) {
        const std::size_t begin = out.text.size();
        out.text += Json(std::string(kBeyondDouble) + token).dump();  // a JSON string: \u0001 escaped
        out.shifts.push_back({begin, out.text.size(), i, i + length});
      } else {
        out.text += token;
      }
      i += length;
    } else {
      out.text += source[i++];
    }
  }
  return out;
}


/// "line L, column C" of the position after reading `read` bytes of `text`, counted as
/// nlohmann's lexer counts them (a newline ends a line; the column is the bytes read since).
std::string line_and_column(std::string_view text, std::size_t read) {
  read = std::min(read, text.size() + 1);  // reading the end of the input counts one byte
  std::size_t line = 1, line_start = 0;
  for (std::size_t i = 0; i < std::min(read, text.size()); ++i) {
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(read - line_start);
}

/// nlohmann's explanation of a parse error without its "[json.exception.parse_error.101] parse
/// error at line 3, column 5: " prefix (the position is recomputed by the caller).
std::string parse_error_detail(const std::string& what) {
  const std::size_t column = what.find(", column ");
  if (column != std::string::npos) {
    const std::size_t colon = what.find(": ", column);
    if (colon != std::string::npos) return what.substr(colon + 2);
  }
  const std::size_t bracket = what.find("] ");
  return bracket == std::string::npos ? what : what.substr(bracket + 2);
}


/// The JSON syntax error `e` that parsing `parsed` threw. `parsed` is the user's text itself
/// (`marks` null) or that text with its numbers beyond double range marked (`marks`), whose
/// positions map back to `source`, the user's text.
[[noreturn]] void syntax_error(std::string_view parsed, std::string_view source, const Json::parse_error& e,
                               const MarkedText* marks) {
  const std::size_t read = marks != nullptr ? marks->source_offset(e.byte) : e.byte;
  const std::string where = io::json_path_at_syntax_error(parsed);
  throw JsonFieldError(where == "root" ? "" : io::valid_utf8(where),
                       io::valid_utf8("JSON syntax error at " + line_and_column(source, read) + ": " +
                                  parse_error_detail(e.what())));
}

// ---- shapes ------------------------------------------------------------------------------------

/// Runs a library constructor, its InvalidInput becoming an error at `path`.
template <class F>
auto build(const JsonPath& path, F&& make) {
  try {
    return make();
  } catch (const InvalidInput& e) {
    fail_json(path, e.what());
  }
}

/// A value as JSON prints it back (1e39 -> 1e+39), for messages.
std::string shown(const Json& j) { return beyond_double(j) ? std::string(beyond_double_token(j)) : j.dump(); }

float radius_from_json(const Json& shape, const JsonPath& path, bool required) {
  const Json* r = find_member(shape, "radius");
  if (r == nullptr) {
    if (required) fail_json(path.member("radius"), "missing");
    return 0.0f;
  }
  const float v = float_from_json(*r, path.member("radius"));
  if (v < 0.0f) fail_json(path.member("radius"), "negative (" + shown(*r) + ")");
  return v;
}

std::vector<Vec2> points_from_json(const Json& j, const JsonPath& path) {
  if (!j.is_array()) fail_json(path, "expected an array of [x, y] points, got " + json_kind(j));
  std::vector<Vec2> out;
  out.reserve(j.size());
  for (std::size_t i = 0; i < j.size(); ++i) out.push_back(vec2_from_json(j[i], path.element(i)));
  return out;
}

/// The points of a `hull` (at most kMaxJsonHullPoints) or a `triangle`: an array of [x, y, z].
std::vector<Vec3> points3_from_json(const Json& j, const JsonPath& path) {
  if (!j.is_array()) fail_json(path, "expected an array of [x, y, z] points, got " + json_kind(j));
  std::vector<Vec3> out;
  out.reserve(j.size());
  for (std::size_t i = 0; i < j.size(); ++i) out.push_back(vec3_from_json(j[i], path.element(i)));
  return out;
}

/// Which reader is asking: one convex shape of either dimension (the query protocol), or the
/// convex pieces of a 2D shape (scene files: concave polygons and polylines too).
enum class ShapeMode : unsigned char { convex, pieces };

/// The shape types and what each may hold.
struct ShapeType {
  std::string_view name;
  int dims;                      ///< 2 or 3 when the type tells; 0 when the coordinates do
  std::string_view coordinates;  ///< the member whose count tells the dimension ("" if fixed)
  int dims_without;              ///< dims when `coordinates` is absent: 2, or 0 (the caller's)
};
constexpr ShapeType kShapeTypes[] = {
    {"circle", 0, "center", 2}, {"sphere", 0, "center", 0}, {"capsule", 0, "a", 0},
    {"segment", 0, "a", 0},     {"box", 0, "half", 0},      {"polygon", 2, "", 0},
    {"polyline", 2, "", 0},     {"hull", 3, "", 0},         {"triangle", 3, "", 0},
};

const ShapeType* find_shape_type(std::string_view name) noexcept {
  for (const ShapeType& t : kShapeTypes) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

JsonDimension dimension_from(int dims) noexcept { return dims == 3 ? JsonDimension::three : JsonDimension::two; }

/// The head of a shape object: its type (validated) and its dimension.
struct ShapeHead {
  std::string_view type;
  JsonDimension dimension = JsonDimension::two;
  std::string_view told_by;  ///< the member that told the dimension ("type", "center"...), or ""
};

ShapeHead read_head(const Json& j, const JsonPath& path, ShapeMode mode, JsonDimension untold) {
  check_object(j, path, "a shape");
  const std::string& type = string_from_json(require_member(j, path, "type"), path.member("type"));
  const ShapeType* known = find_shape_type(type);
  if (known == nullptr) {
    fail_json(path.member("type"),
              "unknown shape type " + Json(type).dump() + " (expected " +
                  (mode == ShapeMode::pieces ? "circle, capsule, box, polygon, segment or polyline"
                                             : "circle, sphere, capsule, box, polygon, segment, hull or triangle") +
                  ")");
  }
  ShapeHead head{known->name, untold, ""};
  // Coordinates that tell nothing (absent, or not 2 or 3 numbers): the caller's dimension, in
  // which they are then read (and rejected).
  if (const std::optional<JsonDimensionCue> cue = shape_dimension_cue(j)) {
    head.dimension = cue->dimension;
    head.told_by = cue->field;
  }
  return head;
}

/// A convex 2D shape of `head.type` (not a polyline, not a concave polygon).
Shape2D read_convex_2d(const Json& j, const JsonPath& path, const ShapeHead& head, ShapeMode mode) {
  const std::string_view type = head.type;
  if (type == "circle" || type == "sphere") {
    check_fields(j, path, {"type", "center", "radius"});
    const Json* c = find_member(j, "center");
    const Vec2 center = c == nullptr ? Vec2{0.0f, 0.0f} : vec2_from_json(*c, path.member("center"));
    const float r = radius_from_json(j, path, true);
    return build(path, [&] { return make_circle(center, r); });
  }
  if (type == "capsule") {
    check_fields(j, path, {"type", "a", "b", "radius"});
    const Vec2 a = vec2_from_json(require_member(j, path, "a"), path.member("a"));
    const Vec2 b = vec2_from_json(require_member(j, path, "b"), path.member("b"));
    const float r = radius_from_json(j, path, true);
    return build(path, [&] { return make_capsule(a, b, r); });
  }
  if (type == "segment") {
    check_fields(j, path, {"type", "a", "b"});
    const Vec2 a = vec2_from_json(require_member(j, path, "a"), path.member("a"));
    const Vec2 b = vec2_from_json(require_member(j, path, "b"), path.member("b"));
    return build(path, [&] { return make_segment(a, b); });
  }
  if (type == "box") {
    check_fields(j, path, {"type", "half", "radius"});
    const Vec2 half = vec2_from_json(require_member(j, path, "half"), path.member("half"));
    if (!(half.x > 0.0f && half.y > 0.0f)) fail_json(path.member("half"), "half extents must be > 0");
    const float r = radius_from_json(j, path, false);
    return build(path, [&] { return make_box(half, r); });
  }
  // polygon (read_shape sends polylines and concave polygons elsewhere)
  if (mode == ShapeMode::pieces) {
    check_fields(j, path, {"type", "vertices", "radius", "concave"});
  } else {
    if (find_member(j, "concave") != nullptr) {
      fail_json(path.member("concave"),
                "a concave polygon is several convex pieces; one convex shape is expected here");
    }
    check_fields(j, path, {"type", "vertices", "radius"});
  }
  const JsonPath vertices_path = path.member("vertices");
  const std::vector<Vec2> vertices = points_from_json(require_member(j, path, "vertices"), vertices_path);
  const float r = radius_from_json(j, path, false);
  try {
    return make_convex_polygon(vertices, r);
  } catch (const InvalidInput& e) {
    fail_json(vertices_path, std::string(e.what()) + (mode == ShapeMode::pieces
                                                          ? "; for a concave or clockwise outline add \"concave\": true"
                                                          : ""));
  }
}

/// Rejects, at `path`, a hull that `make_convex_hull` had to stop at kMaxHullVertices: some
/// input point is then farther than the hull's tolerance outside a face plane (without the cap
/// every point lies within it: convex_hull.hpp, "Every face plane supports the hull").
void check_hull_complete(const ConvexHull& hull, const std::vector<Vec3>& points, const JsonPath& path) {
  if (hull.vertex_count() < kMaxHullVertices) return;
  for (const Vec3& p : points) {
    for (const HullFace& f : hull.faces) {
      if (glm::dot(f.normal, p) - f.offset > hull.tolerance) {
        fail_json(path, "the convex hull of these " + std::to_string(points.size()) + " points has more than " +
                            std::to_string(kMaxHullVertices) + " vertices (the library's limit, kMaxHullVertices)");
      }
    }
  }
}

/// A convex 3D shape or a triangle of `head.type`: sphere {center, radius}, capsule {a, b,
/// radius}, segment {a, b}, box {half, radius?}, hull {points, radius?}, triangle {vertices}.
AnyShape read_3d(const Json& j, const JsonPath& path, const ShapeHead& head) {
  const std::string_view type = head.type;
  if (type == "circle" || type == "sphere") {
    check_fields(j, path, {"type", "center", "radius"});
    const Json* c = find_member(j, "center");
    const Vec3 center = c == nullptr ? Vec3{0.0f} : vec3_from_json(*c, path.member("center"));
    const float r = radius_from_json(j, path, true);
    return Shape3D{build(path, [&] { return make_sphere(center, r); })};
  }
  if (type == "capsule") {
    check_fields(j, path, {"type", "a", "b", "radius"});
    const Vec3 a = vec3_from_json(require_member(j, path, "a"), path.member("a"));
    const Vec3 b = vec3_from_json(require_member(j, path, "b"), path.member("b"));
    const float r = radius_from_json(j, path, true);
    return Shape3D{build(path, [&] { return make_capsule(a, b, r); })};
  }
  if (type == "segment") {
    check_fields(j, path, {"type", "a", "b"});
    const Vec3 a = vec3_from_json(require_member(j, path, "a"), path.member("a"));
    const Vec3 b = vec3_from_json(require_member(j, path, "b"), path.member("b"));
    return Shape3D{build(path, [&] { return make_segment(a, b); })};
  }
  if (type == "box") {
    check_fields(j, path, {"type", "half", "radius"});
    const Vec3 half = vec3_from_json(require_member(j, path, "half"), path.member("half"));
    if (!(half.x > 0.0f && half.y > 0.0f && half.z > 0.0f)) fail_json(path.member("half"), "half extents must be > 0");
    const float r = radius_from_json(j, path, false);
    return Shape3D{build(path, [&] { return make_box(half, r); })};
  }
  if (type == "hull") {
    check_fields(j, path, {"type", "points", "radius"});
    const JsonPath points_path = path.member("points");
    const Json& points_json = require_member(j, path, "points");
    if (points_json.is_array() && points_json.size() > kMaxJsonHullPoints) {
      fail_json(points_path, std::to_string(points_json.size()) + " points; at most " +
                                 std::to_string(kMaxJsonHullPoints) + " (the limit, kMaxJsonHullPoints)");
    }
    const std::vector<Vec3> points = points3_from_json(points_json, points_path);
    const float r = radius_from_json(j, path, false);
    ConvexHull hull = build(points_path, [&] { return make_convex_hull(points, HullOptions{.radius = r}); });
    check_hull_complete(hull, points, points_path);
    return Shape3D{std::move(hull)};
  }
  // triangle
  check_fields(j, path, {"type", "vertices"});
  const JsonPath vertices_path = path.member("vertices");
  const Json& vertices_json = require_member(j, path, "vertices");
  if (vertices_json.is_array() && vertices_json.size() != 3) {
    fail_json(vertices_path, "a triangle has exactly 3 vertices, got " + std::to_string(vertices_json.size()));
  }
  const std::vector<Vec3> v = points3_from_json(vertices_json, vertices_path);
  return build(vertices_path, [&] { return make_triangle(v[0], v[1], v[2]); });
}
}  // namespace

// ---- paths and errors --------------------------------------------------------------------------

std::string JsonPath::str() const {
  if (step_ == Step::root) return {};
  std::string out = parent_->str();
  if (step_ == Step::element) {
    out.append("[").append(std::to_string(index_)).append("]");
  } else {
    if (!out.empty()) out += '.';
    io::append_path_key(out, key_);
  }
  return out;
}

JsonFieldError::JsonFieldError(std::string path, std::string reason)
    : InvalidInput((path.empty() ? std::string("root") : path) + ": " + reason),
      path_(std::move(path)),
      reason_(std::move(reason)) {}

void fail_json(const JsonPath& path, std::string reason) { throw JsonFieldError(path.str(), std::move(reason)); }

// ---- JSON text ---------------------------------------------------------------------------------

Json parse_json(std::string_view text) {
  if (const std::size_t at = io::json_too_deep_at(text, kMaxJsonDepth); at != std::string_view::npos) {
    const std::string where = io::json_path_at_syntax_error(text.substr(0, at));
    throw JsonFieldError(where == "root" ? "" : where,
                         "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels (the limit) at " +
                             line_and_column(text, at + 1));
  }
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& e) {
    syntax_error(text, text, e, nullptr);
  } catch (const Json::out_of_range& e) {
    if (e.id != 406) throw;  // 406: a number beyond double range
  }
  const MarkedText marked = mark_numbers_beyond_double(text);
  try {
    return Json::parse(marked.text);
  } catch (const Json::parse_error& e) {
    syntax_error(marked.text, text, e, &marked);
  } catch (const Json::exception& e) {  // a number the marking missed: still an error naming the place
    const std::string where = io::json_path_at_syntax_error(marked.text);
    throw JsonFieldError(where == "root" ? "" : io::valid_utf8(where),
                         io::valid_utf8(std::string("JSON number out of range: ") + parse_error_detail(e.what())));
  }
}

std::string json_kind(const Json& j) {
  if (beyond_double(j)) return "a number beyond double range (" + std::string(beyond_double_token(j)) + ")";
  return j.type_name();
}

void check_fields(const Json& object, const JsonPath& path, std::initializer_list<std::string_view> allowed) {
  for (auto it = object.begin(); it != object.end(); ++it) {
    const std::string& key = it.key();
    if (key == "comment" || std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::string list;
    for (const std::string_view a : allowed) list.append(list.empty() ? "" : ", ").append(a);
    fail_json(path.member(key), "unknown field (expected one of: " + list + ", comment)");
  }
}

void check_object(const Json& j, const JsonPath& path, std::string_view what) {
  if (!j.is_object()) fail_json(path, "expected " + std::string(what) + " (a JSON object), got " + json_kind(j));
}

const Json& require_member(const Json& object, const JsonPath& path, std::string_view key) {
  const Json* found = find_member(object, key);
  if (found == nullptr) fail_json(path.member(key), "missing");
  return *found;
}

const Json* find_member(const Json& object, std::string_view key) {
  if (!object.is_object()) return nullptr;
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

float float_from_json(const Json& j, const JsonPath& path) {
  if (beyond_double(j)) {
    fail_json(path, "not a finite float (" + std::string(beyond_double_token(j)) + " is beyond double range)");
  }
  if (!j.is_number()) fail_json(path, "expected a number, got " + json_kind(j));
  const double d = j.get<double>();
  const auto f = static_cast<float>(d);
  if (!std::isfinite(d) || !std::isfinite(f)) fail_json(path, "not a finite float (" + shown(j) + ")");
  return f;
}

bool bool_from_json(const Json& j, const JsonPath& path) {
  if (!j.is_boolean()) fail_json(path, "expected true or false, got " + json_kind(j));
  return j.get<bool>();
}

const std::string& string_from_json(const Json& j, const JsonPath& path) {
  if (!j.is_string() || beyond_double(j)) fail_json(path, "expected a string, got " + json_kind(j));
  return j.get_ref<const std::string&>();
}

Vec2 vec2_from_json(const Json& j, const JsonPath& path) {
  if (!j.is_array()) fail_json(path, "expected [x, y], got " + json_kind(j));
  if (j.size() != 2) {
    fail_json(path, "expected 2 numbers, got " + std::to_string(j.size()) +
                        (j.size() == 3 ? " (3D coordinates where 2D is expected)" : ""));
  }
  return {float_from_json(j[0], path.element(0)), float_from_json(j[1], path.element(1))};
}

Vec3 vec3_from_json(const Json& j, const JsonPath& path) {
  if (!j.is_array()) fail_json(path, "expected [x, y, z], got " + json_kind(j));
  if (j.size() != 3) {
    fail_json(path, "expected 3 numbers, got " + std::to_string(j.size()) +
                        (j.size() == 2 ? " (2D coordinates where 3D is expected)" : ""));
  }
  return {float_from_json(j[0], path.element(0)), float_from_json(j[1], path.element(1)),
          float_from_json(j[2], path.element(2))};
}

// ---- shapes ------------------------------------------------------------------------------------

JsonDimension dimension_of(const AnyShape& shape) noexcept {
  return std::holds_alternative<Shape2D>(shape) ? JsonDimension::two : JsonDimension::three;
}

const char* type_name(const AnyShape& shape) noexcept {
  if (const auto* s2 = std::get_if<Shape2D>(&shape)) return type_name(*s2);
  if (const auto* s3 = std::get_if<Shape3D>(&shape)) return type_name(*s3);
  return "triangle";
}

std::optional<JsonDimensionCue> shape_dimension_cue(const Json& shape) {
  const Json* type = find_member(shape, "type");
  if (type == nullptr || !type->is_string() || beyond_double(*type)) return std::nullopt;
  const ShapeType* known = find_shape_type(type->get_ref<const std::string&>());
  if (known == nullptr) return std::nullopt;
  if (known->dims != 0) return JsonDimensionCue{dimension_from(known->dims), "type"};
  const Json* c = find_member(shape, known->coordinates);
  if (c == nullptr) {
    if (known->dims_without != 0) return JsonDimensionCue{dimension_from(known->dims_without), "type"};
    return std::nullopt;
  }
  if (c->is_array() && (c->size() == 2 || c->size() == 3)) {
    return JsonDimensionCue{c->size() == 3 ? JsonDimension::three : JsonDimension::two, known->coordinates};
  }
  return std::nullopt;
}

std::optional<JsonDimensionCue> transform_dimension_cue(const Json& transform) {
  if (find_member(transform, "q") != nullptr) return JsonDimensionCue{JsonDimension::three, "q"};
  if (find_member(transform, "angle") != nullptr) return JsonDimensionCue{JsonDimension::two, "angle"};
  const Json* p = find_member(transform, "p");
  if (p != nullptr && p->is_array() && (p->size() == 2 || p->size() == 3)) {
    return JsonDimensionCue{p->size() == 3 ? JsonDimension::three : JsonDimension::two, "p"};
  }
  return std::nullopt;
}

AnyShape shape_from_json(const Json& j, const JsonPath& path, JsonDimension untold) {
  const ShapeHead head = read_head(j, path, ShapeMode::convex, untold);
  if (head.type == "polyline") {
    fail_json(path.member("type"), "a polyline is several convex pieces; one convex shape is expected here");
  }
  if (head.dimension == JsonDimension::three) return read_3d(j, path, head);
  return read_convex_2d(j, path, head, ShapeMode::convex);
}

void shape_pieces_from_json(const Json& j, const JsonPath& path, std::vector<Shape2D>& out) {
  const ShapeHead head = read_head(j, path, ShapeMode::pieces, JsonDimension::two);
  if (head.dimension == JsonDimension::three) {
    if (head.told_by == "type") {
      fail_json(path.member("type"), "\"" + std::string(head.type) + "\" is a 3D shape; only 2D shapes are accepted here");
    }
    fail_json(path.member(head.told_by), "3D coordinates; only 2D shapes are accepted here");
  }
  if (head.type == "polyline") {
    check_fields(j, path, {"type", "points", "closed"});
    const JsonPath points_path = path.member("points");
    const std::vector<Vec2> p = points_from_json(require_member(j, path, "points"), points_path);
    if (p.size() < 2) fail_json(points_path, "needs at least 2 points, got " + std::to_string(p.size()));
    const Json* closed_json = find_member(j, "closed");
    const bool closed = closed_json != nullptr && bool_from_json(*closed_json, path.member("closed"));
    if (closed && p.size() < 3) fail_json(points_path, "a closed polyline needs at least 3 points");
    const std::size_t links = closed ? p.size() : p.size() - 1;
    for (std::size_t i = 0; i < links; ++i) {
      const std::size_t k = (i + 1) % p.size();
      if (p[i] == p[k]) {
        fail_json(points_path.element(k), "repeats " + points_path.element(i).str() + " (a zero-length link)");
      }
      out.emplace_back(build(points_path.element(k), [&] { return make_segment(p[i], p[k]); }));
    }
    return;
  }
  const Json* concave_json = find_member(j, "concave");
  if (head.type == "polygon" && concave_json != nullptr && bool_from_json(*concave_json, path.member("concave"))) {
    if (find_member(j, "radius") != nullptr) fail_json(path.member("radius"), "not allowed on a concave polygon");
    check_fields(j, path, {"type", "vertices", "concave"});
    const JsonPath vertices_path = path.member("vertices");
    const std::vector<Vec2> vertices = points_from_json(require_member(j, path, "vertices"), vertices_path);
    const std::string name = vertices_path.str();
    std::vector<Shape2D> pieces;
    try {
      pieces = convex_pieces(vertices, name);
    } catch (const InvalidInput& e) {
      std::string why = e.what();  // "NAME: reason"
      if (why.starts_with(name + ": ")) why.erase(0, name.size() + 2);
      throw JsonFieldError(name, why);
    }
    out.insert(out.end(), pieces.begin(), pieces.end());
    return;
  }
  out.push_back(read_convex_2d(j, path, head, ShapeMode::pieces));
}

// ---- transforms --------------------------------------------------------------------------------

Transform transform_from_json(const Json& j, const JsonPath& path) {
  if (!j.is_object()) fail_json(path, "expected {\"p\": [x, y], \"angle\": radians}, got " + json_kind(j));
  if (find_member(j, "q") != nullptr) {
    fail_json(path.member("q"), "a quaternion is a 3D rotation where a 2D transform is expected (\"angle\": radians)");
  }
  check_fields(j, path, {"p", "angle"});
  Vec2 p{0.0f, 0.0f};
  if (const Json* pj = find_member(j, "p")) p = vec2_from_json(*pj, path.member("p"));
  const Json* a = find_member(j, "angle");
  if (a == nullptr) return Transform{p, Rot2{}};
  return Transform::from(p, float_from_json(*a, path.member("angle")));
}

Transform3 transform3_from_json(const Json& j, const JsonPath& path) {
  if (!j.is_object()) fail_json(path, "expected {\"p\": [x, y, z], \"q\": [w, x, y, z]}, got " + json_kind(j));
  if (find_member(j, "angle") != nullptr) {
    fail_json(path.member("angle"), "an angle is a 2D rotation where a 3D transform is expected (\"q\": [w, x, y, z])");
  }
  check_fields(j, path, {"p", "q"});
  Transform3 xf;
  if (const Json* pj = find_member(j, "p")) xf.p = vec3_from_json(*pj, path.member("p"));
  if (const Json* qj = find_member(j, "q")) {
    const JsonPath q_path = path.member("q");
    if (!qj->is_array()) fail_json(q_path, "expected [w, x, y, z], got " + json_kind(*qj));
    if (qj->size() != 4) fail_json(q_path, "expected 4 numbers [w, x, y, z], got " + std::to_string(qj->size()));
    double q[4];
    for (std::size_t k = 0; k < 4; ++k) q[k] = float_from_json((*qj)[k], q_path.element(k));
    const double length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(std::fabs(length - 1.0) <= kJsonUnitQuaternionTolerance)) {
      char why[96];
      std::snprintf(why, sizeof why, "not a unit quaternion (length %g; must be within %g of 1)", length,
                    kJsonUnitQuaternionTolerance);
      fail_json(q_path, why);
    }
    xf.q = Quat{static_cast<float>(q[0] / length), static_cast<float>(q[1] / length),
                static_cast<float>(q[2] / length), static_cast<float>(q[3] / length)};
  }
  return xf;
}

}  // namespace collide
