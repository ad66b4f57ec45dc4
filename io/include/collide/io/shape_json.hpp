#pragma once
/// @file
/// The JSON vocabulary of shapes and transforms, one for every reader: `collide query`
/// (`../shared/spec/query-jsonl.md`) and scene files (`docs/scene-json.md`). The rules it
/// enforces are written once in `docs/shape-json.md`:
///  - JSON text: nesting at most kMaxJsonDepth levels; a number beyond double range (1e400) is
///    not a syntax error but a non-finite number, named by its field when it is read.
///  - Every rejection is a `JsonFieldError` (an `InvalidInput`) whose message starts with the
///    JSON path of the bad value, in one notation: members joined by '.', elements in brackets
///    (`statics[2].shapes[0].radius`, `a.vertices[3][1]`), `root` for the document itself.
///  - Objects take exactly their listed fields plus `"comment"` (any value, ignored); any other
///    field is rejected, naming it.
///  - The dimension is told by the coordinates: 2 numbers 2D, 3 numbers 3D.
///
/// Load time only: these functions allocate. nlohmann::json is part of this header's interface
/// (collide_io links it PUBLIC).

#include <collide/core/error.hpp>
#include <collide/core/transform.hpp>
#include <collide/core/transform3.hpp>
#include <collide/shape/shape2d.hpp>
#include <collide/shape/shape3d.hpp>
#include <collide/shape/triangle.hpp>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace collide {

/// Deepest nesting of arrays and objects `parse_json` accepts (the root object is level 1).
/// Scenes and questions need fewer than 10; the limit keeps a hostile document from
/// exhausting the stack of anything that walks it recursively (copying, printing).
inline constexpr std::size_t kMaxJsonDepth = 256;

/// A quaternion `[w, x, y, z]` is accepted when its length is within this of 1, and then
/// normalised (query-jsonl.md, "Errors"); farther from unit length it is rejected.
inline constexpr double kJsonUnitQuaternionTolerance = 1e-3;

/// Most points a `hull` object may list. Building a hull takes O(n h) time for n points and h
/// faces (make_convex_hull), so the cap bounds the time one shape can take: a `collide query`
/// line with 100,000 points, on a sphere or in a cube, is answered in 0.4 to 0.6 s (release
/// build, mostly reading the 3.5 MB of JSON). Real convex pieces have far fewer points. More
/// are rejected, naming the field and the count.
inline constexpr std::size_t kMaxJsonHullPoints = 100000;

/// Where a value sits in a JSON document: the root, a member of an object, or an element of an
/// array, written "statics[2].shapes[0].radius" (the root alone is the empty string).
///
/// A path refers to its parent and is turned into text only for a message, so reading a valid
/// document builds no strings. Steps are taken from a named path only (`path.member("a")`, not
/// `path.member("a").element(0)`: a step of a temporary would outlive it), so a path lives as
/// long as the variables it was made from: pass it down as a function argument
/// (`shape_from_json(j, path.member("a"))`) or keep it in a local next to its parent.
class JsonPath {
 public:
  /// The root of a document.
  JsonPath() noexcept = default;
  /// The member `key` of the object at this path. `key` must outlive the result.
  [[nodiscard]] JsonPath member(std::string_view key) const& noexcept { return {this, Step::member, key, 0}; }
  /// Element `index` of the array at this path.
  [[nodiscard]] JsonPath element(std::size_t index) const& noexcept { return {this, Step::element, {}, index}; }
  JsonPath member(std::string_view key) const&& = delete;  ///< name the parent first
  JsonPath element(std::size_t index) const&& = delete;    ///< name the parent first
  /// The path as text: "statics[2].shapes[0].radius"; "" for the root.
  [[nodiscard]] std::string str() const;

 private:
  enum class Step : unsigned char { root, member, element };
  JsonPath(const JsonPath* parent, Step step, std::string_view key, std::size_t index) noexcept
      : parent_(parent), step_(step), key_(key), index_(index) {}
  const JsonPath* parent_ = nullptr;  ///< nullptr: the root itself
  Step step_ = Step::root;
  std::string_view key_;              ///< a member's name
  std::size_t index_ = 0;             ///< an element's index
};

/// A rejected JSON value: `what()` is "PATH: reason" ("root: reason" for the document itself).
class JsonFieldError : public InvalidInput {
 public:
  JsonFieldError(std::string path, std::string reason);
  /// The JSON path of the bad value ("" for the root).
  [[nodiscard]] const std::string& path() const noexcept { return path_; }
  /// Why it was rejected, without the path.
  [[nodiscard]] const std::string& reason() const noexcept { return reason_; }

 private:
  std::string path_;
  std::string reason_;
};

/// Throws JsonFieldError(path, reason).
[[noreturn]] void fail_json(const JsonPath& path, std::string reason);

/// Parses one JSON document (a query line, a scene file). Rejects, as a JsonFieldError naming
/// the path being read: nesting deeper than kMaxJsonDepth ("JSON nested deeper than 256 levels
/// (the limit) at line L, column C"), and any syntax error ("JSON syntax error at line L,
/// column C: ..."; bytes that are not UTF-8 are shown as \xNN, so the message is valid UTF-8).
/// A number beyond double range (1e400) is kept as a marked value that every reader below
/// rejects, naming its field: "not a finite float (1e400 is beyond double range)".
[[nodiscard]] nlohmann::json parse_json(std::string_view text);

/// The kind of a JSON value for messages: its JSON type name ("array", "string", ...), or
/// "a number beyond double range (1e400)" for such a number.
[[nodiscard]] std::string json_kind(const nlohmann::json& j);

/// Rejects any member of `object` whose name is neither in `allowed` nor "comment" (any value,
/// ignored everywhere), naming it: "PATH.key: unknown field (expected one of: a, b, comment)".
void check_fields(const nlohmann::json& object, const JsonPath& path,
                  std::initializer_list<std::string_view> allowed);

/// Rejects `j` unless it is an object: "expected WHAT (a JSON object), got array".
void check_object(const nlohmann::json& j, const JsonPath& path, std::string_view what);

/// The member `key` of `object` (an object); rejects "PATH.key: missing" when it is absent.
[[nodiscard]] const nlohmann::json& require_member(const nlohmann::json& object, const JsonPath& path,
                                                   std::string_view key);
/// The member `key` of `object` (an object), or nullptr when it is absent.
[[nodiscard]] const nlohmann::json* find_member(const nlohmann::json& object, std::string_view key);

/// A number that is finite as a 32-bit float; rejects anything else, naming the field and the
/// value ("not a finite float (1e+39)").
[[nodiscard]] float float_from_json(const nlohmann::json& j, const JsonPath& path);
/// `true` or `false`.
[[nodiscard]] bool bool_from_json(const nlohmann::json& j, const JsonPath& path);
/// A string (not a number beyond double range in disguise).
[[nodiscard]] const std::string& string_from_json(const nlohmann::json& j, const JsonPath& path);
/// A 2D point or vector `[x, y]`; 3 numbers are rejected as 3D coordinates.
[[nodiscard]] Vec2 vec2_from_json(const nlohmann::json& j, const JsonPath& path);
/// A 3D point or vector `[x, y, z]`; 2 numbers are rejected as 2D coordinates.
[[nodiscard]] Vec3 vec3_from_json(const nlohmann::json& j, const JsonPath& path);

/// Dimension of a shape, a transform or a question.
enum class JsonDimension : unsigned char { two = 2, three = 3 };

/// A shape of either dimension, as `shape_from_json` returns it: a 2D shape, a convex 3D shape,
/// or a 3D triangle (a surface, not a solid: the library keeps it out of `Shape3D` and gives it
/// overloads of its own). Callers that `std::visit` it handle all three.
using AnyShape = std::variant<Shape2D, Shape3D, Triangle>;

/// The dimension of a shape from `shape_from_json`.
[[nodiscard]] JsonDimension dimension_of(const AnyShape& shape) noexcept;

/// Lower-case name of the shape's type as the vocabulary writes it ("circle", "polygon",
/// "sphere", "hull", "triangle"...; a 2D box is a "polygon"), for messages.
[[nodiscard]] const char* type_name(const AnyShape& shape) noexcept;

/// What a JSON object says of its dimension before it is read: the dimension and the member
/// that tells it.
struct JsonDimensionCue {
  JsonDimension dimension = JsonDimension::two;
  std::string_view field;  ///< the member that tells: "type" (polygon, hull...), "center", "p", "q"...
};

/// The dimension a shape object tells, by the rules of `shape_from_json`: its type (`polygon`
/// and `polyline` are 2D, `hull` and `triangle` 3D, a `circle` without `center` 2D) or the count
/// of its coordinates (`center`, `a` or `half`: 2 numbers 2D, 3 numbers 3D). Nothing
/// (std::nullopt) for a `sphere` without `center`, or an object too malformed to tell (reading
/// it then says what is wrong). Reads no more than the type and the one member.
[[nodiscard]] std::optional<JsonDimensionCue> shape_dimension_cue(const nlohmann::json& shape);

/// The dimension a transform object tells: `q` 3D, `angle` 2D, else `p` by its count; nothing
/// for an empty (identity) or malformed object.
[[nodiscard]] std::optional<JsonDimensionCue> transform_dimension_cue(const nlohmann::json& transform);

/// One convex shape object in local space, 2D or 3D by its coordinates (the `collide query`
/// vocabulary, query-jsonl.md "Shapes"): `circle` or `sphere` (one type, two names) {center,
/// radius}, `capsule` {a, b, radius}, `segment` {a, b}, `box` {half, radius?}, `polygon`
/// {vertices, radius?} (2D, convex, counter-clockwise), `hull` {points, radius?} (3D: the convex
/// hull of 4 to kMaxJsonHullPoints points, at most kMaxHullVertices of them its vertices) and
/// `triangle` {vertices (3)} (3D). A shape whose coordinates do not tell its dimension (a
/// `sphere` without `center`) has the dimension `untold`: the caller's, e.g. the rest of the
/// question's; a `circle` without `center` is 2D. Validated and built by the library's make_*
/// functions; their messages are kept, after the path of the field they concern. Polylines and
/// concave polygons are several pieces, rejected here. Throws JsonFieldError.
[[nodiscard]] AnyShape shape_from_json(const nlohmann::json& j, const JsonPath& path,
                                       JsonDimension untold = JsonDimension::two);

/// One 2D shape object cut into convex pieces (the scene-file vocabulary, docs/scene-json.md):
/// the 2D shapes of `shape_from_json` (a circle or sphere without `center` is 2D), and also `polygon` with `"concave": true` (any simple
/// outline, either winding, cut by `convex_pieces`) and `polyline` {points, closed?} (one
/// Segment per link). Appends the pieces to `out`. 3D shapes are rejected. Throws
/// JsonFieldError.
void shape_pieces_from_json(const nlohmann::json& j, const JsonPath& path, std::vector<Shape2D>& out);

/// A 2D transform `{"p": [x, y], "angle": radians}` (counter-clockwise), local -> world; an
/// omitted member is the identity's. A 3D transform (3 coordinates, `q`) is rejected, naming
/// the field. Throws JsonFieldError.
[[nodiscard]] Transform transform_from_json(const nlohmann::json& j, const JsonPath& path);

/// A 3D transform `{"p": [x, y, z], "q": [w, x, y, z]}`, local -> world; an omitted member is
/// the identity's. The quaternion must be within kJsonUnitQuaternionTolerance of unit length
/// and is normalised. A 2D transform (2 coordinates, `angle`) is rejected, naming the field.
/// Throws JsonFieldError.
[[nodiscard]] Transform3 transform3_from_json(const nlohmann::json& j, const JsonPath& path);

}  // namespace collide
