// The JSON Lines query protocol. Parsing turns JSON into validated shapes through the shared
// JSON vocabulary (collide/io/shape_json.hpp: every rejection names its field), then the library
// answers; formatting writes floats with the fewest digits that round-trip. Reading is bounded
// (kMaxQueryLineBytes per line, kMaxJsonDepth) and no exception leaves a line's handling.

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

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <istream>
#include <new>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <variant>
#include <vector>

namespace collide::cli {
namespace {

using nlohmann::json;

/// A rejected question whose reason is not about one field (the message says it all).
struct QueryError {
  std::string message;
};

/// A float written with the fewest digits that read back as the same float.
json number(float v) {
  if (v == 0.0f) v = 0.0f;  // print -0 as 0
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return json(std::strtod(std::string(buf, res.ptr).c_str(), nullptr));
}

json vec(Vec2 v) { return json::array({number(v.x), number(v.y)}); }

/// The shape in member `key` of question `q` (required). Its dimension tells the question's:
/// 3D shapes are rejected by shape_from_json ("3D shapes: not yet"), so every shape here is 2D,
/// and so is a circle without center. When the library has Shape3D, the ops below gain a 3D
/// branch on dimension_of(shape), and a shape without coordinates takes the other's dimension.
Shape2D shape_field(const json& q, const JsonPath& root, std::string_view key) {
  const AnyShape shape = shape_from_json(require_member(q, root, key), root.member(key), JsonDimension::two);
  return std::get<Shape2D>(shape);
}

/// The 2D transform in member `key` of `q`; omitted: the identity.
Transform transform_field(const json& q, const JsonPath& root, std::string_view key) {
  const json* x = find_member(q, key);
  return x == nullptr ? Transform{} : transform_from_json(*x, root.member(key));
}

/// The 2D point or vector in member `key` of `q` (required).
Vec2 vec2_field(const json& q, const JsonPath& root, std::string_view key) {
  return vec2_from_json(require_member(q, root, key), root.member(key));
}

std::string feature_name(Feature f) {
  const char* kind = f.type == FeatureType::vertex ? "vertex"
                     : f.type == FeatureType::edge ? "edge"
                                                   : "face";
  return std::string(kind) + " " + std::to_string(f.index);
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

CastQuestion to_cast_question(const json& q, const JsonPath& root) {
  CastQuestion c;
  c.a = shape_field(q, root, "a");
  c.b = shape_field(q, root, "b");
  c.xa = transform_field(q, root, "xa");
  c.xb = transform_field(q, root, "xb");
  c.va = vec2_field(q, root, "va");
  c.vb = vec2_field(q, root, "vb");
  return c;
}

json answer(const json& q) {
  const JsonPath root;
  check_object(q, root, "a question");
  const std::string& op = string_from_json(require_member(q, root, "op"), root.member("op"));
  json out;
  if (op == "overlap" || op == "contact" || op == "distance") {
    const Shape2D a = shape_field(q, root, "a");
    const Shape2D b = shape_field(q, root, "b");
    const Transform xa = transform_field(q, root, "xa");
    const Transform xb = transform_field(q, root, "xb");
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
    const Shape2D shape = shape_field(q, root, "shape");
    const Transform x = transform_field(q, root, "x");
    const Ray ray{vec2_field(q, root, "origin"), vec2_field(q, root, "translation")};
    const RayHit hit = raycast(shape, x, ray);
    out["hit"] = hit.hit;
    if (hit.hit) {
      out["fraction"] = number(hit.fraction);
      out["point"] = vec(hit.point);
      out["normal"] = vec(hit.normal);
    }
  } else if (op == "closest_point") {
    const Shape2D shape = shape_field(q, root, "shape");
    const Transform x = transform_field(q, root, "x");
    const Vec2 point = vec2_field(q, root, "point");
    const PointQuery r = closest_point(shape, x, point);
    out["inside"] = r.inside;
    out["distance"] = number(r.distance);
    out["closest"] = vec(r.closest);
    out["feature"] = feature_name(r.feature);
  } else if (op == "pairs") {
    out = answer_pairs(q, root);
  } else if (op == "toi") {
    const CastQuestion c = to_cast_question(q, root);
    ShapeCastResult r;
    try {
      r = shape_cast(c.a, c.xa, c.va, c.b, c.xb, c.vb);
    } catch (const InvalidInput& e) {
      throw QueryError{e.what()};
    }
    if (r.status == QueryStatus::max_iterations) {
      throw QueryError{"time of impact did not converge (iteration cap); no contact before t = " +
                       std::to_string(r.fraction)};
    }
    out["hit"] = r.hit;
    if (r.hit) {
      out["t"] = number(r.fraction);
      out["point"] = vec(r.point);
      out["normal"] = vec(r.normal);
    }
  } else {
    fail_json(root.member("op"), "unknown op " + json(op).dump());  // quoted and escaped
  }
  return out;
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
    return to_cast_question(q, root);
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
      "Shapes and transforms take only these fields (and \"comment\"); 3D shapes: not yet.\n"
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
