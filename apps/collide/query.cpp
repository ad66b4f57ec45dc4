// The JSON Lines query protocol. Parsing turns JSON into validated shapes (every rejection names
// its field), then the library answers; formatting writes floats with the fewest digits that
// round-trip.

#include "query.hpp"

#include <collide/broad/registry.hpp>
#include <collide/ccd/raycast.hpp>
#include <collide/ccd/shape_cast.hpp>
#include <collide/core/error.hpp>
#include <collide/narrow/closest_point.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/narrow/overlap.hpp>

#include <nlohmann/json.hpp>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <istream>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace collide::cli {
namespace {

using nlohmann::json;

/// A rejected question; the message names the field.
struct QueryError {
  std::string message;
};

[[noreturn]] void fail(const std::string& field, const std::string& why) {
  throw QueryError{field.empty() ? why : field + ": " + why};
}

/// A float written with the fewest digits that read back as the same float.
json number(float v) {
  if (v == 0.0f) v = 0.0f;  // print -0 as 0
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return json(std::strtod(std::string(buf, res.ptr).c_str(), nullptr));
}

json vec(Vec2 v) { return json::array({number(v.x), number(v.y)}); }

const json& require(const json& obj, const char* key, const std::string& where) {
  const auto it = obj.find(key);
  if (it == obj.end()) fail(where.empty() ? std::string(key) : where + "." + key, "missing");
  return *it;
}

std::string path(const std::string& where, const std::string& key) {
  return where.empty() ? key : where + "." + key;
}

/// A number beyond double range (1e400) fails JSON parsing before any field is known. Such a
/// line is parsed again with each of those numbers turned into a string starting with this
/// mark (a control character, so no string a user sends by hand): to_float then names the field.
constexpr std::string_view kBeyondDouble = "\x01" "beyond double range: ";

/// `line` with every number beyond double range written as a kBeyondDouble string. Strings are
/// copied as they are: a run of digits inside one is not a number.
std::string mark_numbers_beyond_double(std::string_view line) {
  const auto in_number = [](char c) {
    return (c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '+' || c == '-';
  };
  std::string out;
  bool in_string = false;
  for (std::size_t i = 0; i < line.size();) {
    const char c = line[i];
    if (in_string) {
      if (c == '\\' && i + 1 < line.size()) out += line[i++];  // the escaped char follows
      else if (c == '"') in_string = false;
      out += line[i++];
    } else if (c == '"') {
      in_string = true;
      out += line[i++];
    } else if (c == '-' || (c >= '0' && c <= '9')) {
      std::size_t end = i + 1;
      while (end < line.size() && in_number(line[end])) ++end;
      const std::string token(line.substr(i, end - i));
      if (std::isinf(std::strtod(token.c_str(), nullptr))) {
        out += json(std::string(kBeyondDouble) + token).dump();  // a JSON string: \u0001 escaped
      } else {
        out += token;
      }
      i = end;
    } else {
      out += line[i++];
    }
  }
  return out;
}

float to_float(const json& j, const std::string& field) {
  if (j.is_string() && j.get_ref<const std::string&>().starts_with(kBeyondDouble)) {
    fail(field, "not a finite float (" + j.get<std::string>().substr(kBeyondDouble.size()) +
                    " is beyond double range)");
  }
  if (!j.is_number()) fail(field, "expected a number");
  const double d = j.get<double>();
  const auto f = static_cast<float>(d);
  if (!std::isfinite(d) || !std::isfinite(f)) fail(field, "not a finite float");
  return f;
}

/// A 2D point. 3D coordinates are recognised and rejected with a clear message: this build
/// answers 2D questions only.
Vec2 to_vec2(const json& j, const std::string& field) {
  if (!j.is_array()) fail(field, "expected an array of 2 numbers");
  if (j.size() == 3) fail(field, "3D coordinates: this version answers 2D questions only");
  if (j.size() != 2) fail(field, "expected 2 numbers, got " + std::to_string(j.size()));
  return {to_float(j[0], field + "[0]"), to_float(j[1], field + "[1]")};
}

float radius_field(const json& shape, const std::string& where, bool required) {
  const auto it = shape.find("radius");
  if (it == shape.end()) {
    if (required) fail(path(where, "radius"), "missing");
    return 0.0f;
  }
  const float r = to_float(*it, path(where, "radius"));
  if (r < 0.0f) fail(path(where, "radius"), "negative");
  return r;
}

/// Runs a library constructor, turning its InvalidInput into an error naming the field.
template <class F>
auto build(const std::string& where, F&& make) {
  try {
    return make();
  } catch (const InvalidInput& e) {
    fail(where, e.what());
  }
}

Shape2D to_shape(const json& j, const std::string& where) {
  if (!j.is_object()) fail(where, "expected a shape object");
  const json& type_json = require(j, "type", where);
  if (!type_json.is_string()) fail(path(where, "type"), "expected a string");
  const std::string type = type_json.get<std::string>();
  if (type == "circle" || type == "sphere") {
    const auto c = j.find("center");
    const Vec2 center = c == j.end() ? Vec2{0.0f, 0.0f} : to_vec2(*c, path(where, "center"));
    const float r = radius_field(j, where, true);
    return build(where, [&] { return make_circle(center, r); });
  }
  if (type == "capsule") {
    const Vec2 a = to_vec2(require(j, "a", where), path(where, "a"));
    const Vec2 b = to_vec2(require(j, "b", where), path(where, "b"));
    const float r = radius_field(j, where, true);
    return build(where, [&] { return make_capsule(a, b, r); });
  }
  if (type == "segment") {
    const Vec2 a = to_vec2(require(j, "a", where), path(where, "a"));
    const Vec2 b = to_vec2(require(j, "b", where), path(where, "b"));
    return build(where, [&] { return make_segment(a, b); });
  }
  if (type == "box") {
    const Vec2 half = to_vec2(require(j, "half", where), path(where, "half"));
    const float r = radius_field(j, where, false);
    return build(where, [&] { return make_box(half, r); });
  }
  if (type == "polygon") {
    const json& vs = require(j, "vertices", where);
    const std::string field = path(where, "vertices");
    if (!vs.is_array()) fail(field, "expected an array of points");
    std::vector<Vec2> points;
    for (size_t i = 0; i < vs.size(); ++i) {
      points.push_back(to_vec2(vs[i], field + "[" + std::to_string(i) + "]"));
    }
    const float r = radius_field(j, where, false);
    return build(where, [&] { return make_convex_polygon(points, r); });
  }
  if (type == "hull" || type == "triangle") {
    fail(path(where, "type"), "\"" + type + "\" is a 3D shape: this version answers 2D questions only");
  }
  fail(path(where, "type"), "unknown shape type \"" + type + "\"");
}

Transform to_transform(const json& q, const char* key) {
  const auto it = q.find(key);
  if (it == q.end()) return Transform{};
  const std::string where = key;
  if (!it->is_object()) fail(where, "expected {\"p\": [x, y], \"angle\": radians}");
  Transform xf;
  if (const auto p = it->find("p"); p != it->end()) xf.p = to_vec2(*p, where + ".p");
  if (it->contains("q")) fail(where + ".q", "quaternions are 3D: this version answers 2D questions only");
  if (const auto a = it->find("angle"); a != it->end()) {
    xf.q = Rot2::from_angle(to_float(*a, where + ".angle"));
  }
  return xf;
}

std::string feature_name(Feature f) {
  const char* kind = f.type == FeatureType::vertex ? "vertex"
                     : f.type == FeatureType::edge ? "edge"
                                                   : "face";
  return std::string(kind) + " " + std::to_string(f.index);
}

/// The `boxes` of a `pairs` question: each [minx, miny, maxx, maxy] (2D) or
/// [minx, miny, minz, maxx, maxy, maxz] (3D), one dimension for all.
json answer_pairs(const json& q) {
  const json& boxes = require(q, "boxes", "");
  if (!boxes.is_array()) fail("boxes", "expected an array of boxes");
  std::string name;
  if (const auto it = q.find("broadphase"); it != q.end()) {
    if (!it->is_string()) fail("broadphase", "expected a name");
    name = it->get<std::string>();
  }
  const size_t width = boxes.empty() || !boxes[0].is_array() ? 4 : boxes[0].size();
  if (width != 4 && width != 6) fail("boxes[0]", "expected 4 (2D) or 6 (3D) numbers");
  std::vector<Aabb> boxes2;
  std::vector<Aabb3> boxes3;
  for (size_t i = 0; i < boxes.size(); ++i) {
    const std::string field = "boxes[" + std::to_string(i) + "]";
    const json& b = boxes[i];
    if (!b.is_array() || b.size() != width) {
      fail(field, "expected " + std::to_string(width) + " numbers like boxes[0]");
    }
    float v[6];
    for (size_t k = 0; k < width; ++k) v[k] = to_float(b[k], field + "[" + std::to_string(k) + "]");
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
    fail(why.rfind("box ", 0) == 0 ? "boxes" : "", why);
  }
  json out = json::array();
  for (const auto& [i, j] : pairs) out.push_back(json::array({i, j}));
  return json::object({{"pairs", out}});
}

CastQuestion to_cast_question(const json& q) {
  CastQuestion c;
  c.a = to_shape(require(q, "a", ""), "a");
  c.b = to_shape(require(q, "b", ""), "b");
  c.xa = to_transform(q, "xa");
  c.xb = to_transform(q, "xb");
  c.va = to_vec2(require(q, "va", ""), "va");
  c.vb = to_vec2(require(q, "vb", ""), "vb");
  return c;
}

json answer(const json& q) {
  if (!q.is_object()) fail("", "expected a JSON object");
  const json& op_json = require(q, "op", "");
  if (!op_json.is_string()) fail("op", "expected a string");
  const std::string op = op_json.get<std::string>();
  json out;
  if (op == "overlap" || op == "contact" || op == "distance") {
    const Shape2D a = to_shape(require(q, "a", ""), "a");
    const Shape2D b = to_shape(require(q, "b", ""), "b");
    const Transform xa = to_transform(q, "xa");
    const Transform xb = to_transform(q, "xb");
    if (op == "overlap") {
      out["overlap"] = overlap(a, xa, b, xb);
    } else if (op == "contact") {
      const Manifold m = contact(a, xa, b, xb);
      out["touching"] = m.touching();
      if (m.touching()) {
        out["normal"] = vec(m.normal);
        out["depth"] = number(m.max_depth());
        json points = json::array();
        json depths = json::array();
        for (int i = 0; i < m.count; ++i) {
          points.push_back(vec(m.points[i].point));
          depths.push_back(number(m.points[i].depth));
        }
        out["points"] = points;
        out["depths"] = depths;
      }
    } else {
      const DistanceResult d = distance(a, xa, b, xb);
      out["distance"] = number(d.distance);
      out["pa"] = vec(d.point_a);
      out["pb"] = vec(d.point_b);
    }
  } else if (op == "raycast") {
    const Shape2D shape = to_shape(require(q, "shape", ""), "shape");
    const Transform x = to_transform(q, "x");
    const Ray ray{to_vec2(require(q, "origin", ""), "origin"),
                  to_vec2(require(q, "translation", ""), "translation")};
    const RayHit hit = raycast(shape, x, ray);
    out["hit"] = hit.hit;
    if (hit.hit) {
      out["fraction"] = number(hit.fraction);
      out["point"] = vec(hit.point);
      out["normal"] = vec(hit.normal);
    }
  } else if (op == "closest_point") {
    const Shape2D shape = to_shape(require(q, "shape", ""), "shape");
    const Transform x = to_transform(q, "x");
    const Vec2 point = to_vec2(require(q, "point", ""), "point");
    const PointQuery r = closest_point(shape, x, point);
    out["inside"] = r.inside;
    out["distance"] = number(r.distance);
    out["closest"] = vec(r.closest);
    out["feature"] = feature_name(r.feature);
  } else if (op == "pairs") {
    out = answer_pairs(q);
  } else if (op == "toi") {
    const CastQuestion c = to_cast_question(q);
    ShapeCastResult r;
    try {
      r = shape_cast(c.a, c.xa, c.va, c.b, c.xb, c.vb);
    } catch (const InvalidInput& e) {
      fail("", e.what());
    }
    if (r.status == QueryStatus::max_iterations) {
      fail("", "time of impact did not converge (iteration cap); no contact before t = " +
                   std::to_string(r.fraction));
    }
    out["hit"] = r.hit;
    if (r.hit) {
      out["t"] = number(r.fraction);
      out["point"] = vec(r.point);
      out["normal"] = vec(r.normal);
    }
  } else {
    fail("op", "unknown op \"" + op + "\"");
  }
  return out;
}

}  // namespace

std::string answer_query_line(std::string_view line) {
  if (line.find_first_not_of(" \t\r\n") == std::string_view::npos) return {};
  json id = nullptr;
  json out;
  try {
    json q;
    try {
      q = json::parse(line);
    } catch (const json::out_of_range& e) {
      if (e.id != 406) throw;  // 406: a number beyond double range
      q = json::parse(mark_numbers_beyond_double(line));
    }
    if (q.is_object()) {
      if (const auto it = q.find("id"); it != q.end()) id = *it;
    }
    out = answer(q);
  } catch (const json::exception& e) {
    // Syntax errors (numbers beyond double range are marked and named by to_float instead).
    out = json::object({{"error", std::string("line is not valid JSON: ") + e.what()}});
  } catch (const QueryError& e) {
    out = json::object({{"error", e.message}});
  } catch (const std::exception& e) {
    out = json::object({{"error", std::string("internal error: ") + e.what()}});
  }
  json result = json::object({{"id", id}});
  result.update(out);
  return result.dump();
}

CastQuestion parse_cast_question(std::string_view text) {
  try {
    const json q = json::parse(text);
    if (!q.is_object()) fail("", "expected a JSON object");
    if (const auto op = q.find("op"); op != q.end() && *op != "toi") {
      fail("op", "a cast question is a \"toi\" question");
    }
    return to_cast_question(q);
  } catch (const json::exception& e) {
    throw InvalidInput(std::string("not valid JSON: ") + e.what());
  } catch (const QueryError& e) {
    throw InvalidInput(e.message);
  }
}

std::size_t answer_query_stream(std::istream& in, std::ostream& out) {
  std::size_t answered = 0;
  std::string line;
  while (std::getline(in, line)) {
    const std::string reply = answer_query_line(line);
    if (reply.empty()) continue;
    out << reply << '\n';
    ++answered;
  }
  out.flush();
  return answered;
}

std::string query_ops_help() {
  std::string text =
      "Ops (one JSON object per line; every answer echoes \"id\"):\n"
      "  overlap        a, xa, b, xb                 -> overlap\n"
      "  contact        a, xa, b, xb                 -> touching, normal (A to B), depth, points, depths\n"
      "  distance       a, xa, b, xb                 -> distance, pa, pb\n"
      "  raycast        shape, x, origin, translation -> hit, fraction, point, normal\n"
      "  closest_point  shape, x, point               -> inside, distance (signed), closest, feature\n"
      "  toi            a, xa, va, b, xb, vb          -> hit, t (first touch in [0, 1]), point, normal\n"
      "  pairs          boxes, broadphase?            -> pairs ([i, j], i < j, sorted, each once)\n"
      "Shapes: circle {center, radius}, capsule {a, b, radius}, box {half, radius?},\n"
      "        polygon {vertices (convex, counter-clockwise), radius?}, segment {a, b}\n"
      "Transforms: {\"p\": [x, y], \"angle\": radians}; omitted means identity.\n"
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
