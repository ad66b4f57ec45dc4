#pragma once
/// @file
/// 3D pictures: debug geometry recorded through DebugDraw3 (core/debug_draw.hpp), rendered in
/// perspective by our own small rasterizer with a depth buffer (no library in Debian fits a
/// depth-tested software render of a few hundred thousand triangles and stays small), then
/// finished with Cairo: the strokes (lasers, paths, normals), points, titles and legend,
/// anti-aliased, and the PNG file.
///
/// How a picture reads: solids are flat-shaded in their role's colour (draw_style) by a sun
/// above and a light at the eye, with a dark outline where the depth jumps or the role changes
/// (silhouettes), rendered at kViewSupersample times the size and averaged down (anti-aliased
/// edges). Static geometry can be cut away where it faces away from the camera
/// (View3DOptions::cutaway): seen from outside, a closed room shows its inside. Strokes and
/// points are tested against the depth buffer along their length: the parts in view are drawn
/// solid, the parts behind a surface faint and dashed, so a laser's path or a contact under a
/// body is never lost.

#include <collide/core/aabb.hpp>
#include <collide/core/debug_draw.hpp>
#include <collide/core/math.hpp>
#include <collide/draw/palette.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace collide {

/// Vertical field of view of the cameras `camera_framing` makes, radians (40 degrees).
inline constexpr float kDefaultFovY = 0.6981317f;
/// The renderer draws at this many times the picture's size on each axis and averages down.
inline constexpr int kViewSupersample = 2;
/// Largest picture side, pixels (keeps a mistyped size from allocating gigabytes).
inline constexpr int kMaxViewSide = 8192;

/// A pinhole camera, world space.
struct Camera3 {
  Vec3 eye{0.0f, 0.0f, 10.0f};     ///< where it is
  Vec3 target{0.0f, 0.0f, 0.0f};   ///< the point at the picture's centre
  Vec3 up{0.0f, 1.0f, 0.0f};       ///< world direction that points up the picture (not along the view)
  float fov_y = kDefaultFovY;      ///< vertical field of view, radians, in (0, pi)
};

/// A picture's width over its height, unless View3DOptions::view_height says otherwise.
inline constexpr float kDefaultViewAspect = 1.6f;

/// A camera that sees all of `box` (world space) centred, from the direction given by
/// `azimuth` (radians, about +y; 0 looks along -z from +z) and `elevation` (radians above the
/// horizontal plane, in [-pi/2, pi/2]; straight down has -z up the picture), at the nearest
/// distance where every corner of the box is in a view of `aspect` (width over height),
/// divided by `zoom` (> 0; 2 is twice as close). y is up.
[[nodiscard]] Camera3 camera_framing(const Aabb3& box, float azimuth, float elevation, float zoom = 1.0f,
                                     float fov_y = kDefaultFovY, float aspect = kDefaultViewAspect);

/// One view of a picture: a camera, the caption above it, and where the level is cut.
struct View3DPanel {
  Camera3 camera;
  std::string title;
  /// Static geometry above this world height (y) is cut away, walls cut through at it (an
  /// architect's section): rooms with roofs show their floors. None: nothing is cut.
  std::optional<float> cut_above;
  /// Everything nearer to the eye than this distance (world units, along the view direction) is
  /// cut away: a close-up sees through the bodies between its camera and what it frames. None:
  /// only the camera's own near plane (a tiny fraction of the distance to the target).
  std::optional<float> cut_nearer;
  /// The roles this view shows (solids, strokes and points); empty: every role. Panels of one
  /// picture can so show different things side by side (an input and what was made of it).
  std::vector<DrawRole> roles;
};

/// How a 3D picture is laid out. Checked by `render`.
struct View3DOptions {
  int width = 1400;       ///< picture width, pixels, [64, kMaxViewSide]
  /// Height of each view, pixels, [0, kMaxViewSide]; 0: its width over kDefaultViewAspect.
  int view_height = 0;
  std::string title;      ///< top line; empty: none
  bool legend = true;     ///< a line naming each role drawn, with its swatch
  /// Static geometry facing away from the camera is not drawn (its triangles' normals by the
  /// right-hand rule, counter-clockwise seen from the front): a room seen from outside shows
  /// its inside. Levels wound the other way show their outside only; turn this off for them.
  bool cutaway = true;
};

/// A rendered 3D picture, kept for inspection (tests) and written as PNG.
struct View3DImage {
  int width = 0;
  int height = 0;
  /// Pixels, row by row from the top, 4 bytes each in Cairo's ARGB32 order (premultiplied,
  /// native endian: a std::uint32_t per pixel, 0xAARRGGBB).
  std::vector<std::uint32_t> pixels;
  /// Where each view landed: its left, top, width and height, pixels.
  std::vector<std::array<int, 4>> views;

  /// The pixel at column x, row y, as 0xAARRGGBB.
  [[nodiscard]] std::uint32_t at(int x, int y) const noexcept {
    return pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)];
  }
};

/// Where a world point lands in a view: image pixels (x right, y down) and its depth along the
/// camera's view axis (world units); nothing for a point behind the near plane.
struct ViewPoint {
  Vec2 pixel{0.0f, 0.0f};
  float depth = 0.0f;
};
[[nodiscard]] std::optional<ViewPoint> project(const Camera3& camera, int view_width, int view_height, Vec3 p) noexcept;

/// A 3D picture: records DebugDraw3 calls (world space), then renders them through one or more
/// cameras side by side. Roles keep the colours of the 2D pictures (draw_style).
class Picture3D final : public DebugDraw3 {
 public:
  void draw_triangle(const Vec3& a, const Vec3& b, const Vec3& c, DrawRole role) override;
  void draw_segment(const Vec3& a, const Vec3& b, DrawRole role) override;
  void draw_arrow(const Vec3& from, const Vec3& to, DrawRole role) override;
  void draw_point(const Vec3& p, DrawRole role) override;
  /// A solid triangle of `role` filled with its own colour `fill` (opaque: its alpha is not
  /// used) instead of the role's, shaded the same way: things of one role told apart by colour
  /// (each hull of a decomposition). Solids of different colours are outlined where they meet,
  /// as solids of different roles are. The legend still shows the role's own swatch.
  void draw_triangle(const Vec3& a, const Vec3& b, const Vec3& c, DrawRole role, Color fill);

  /// The legend's name for `role` (default: to_string(role)), e.g. "characters" for highlight.
  void set_role_name(DrawRole role, std::string name);

  /// Renders every view. Throws InvalidInput for a width or view height out of range, no view,
  /// or a camera that is not finite, has a zero view direction, an `up` along it, or a field
  /// of view outside (0, pi).
  [[nodiscard]] View3DImage render(const std::vector<View3DPanel>& views, const View3DOptions& options) const;

  /// `render`, written as a PNG file. Throws InvalidInput naming `path` when it cannot be written.
  void write_png(const std::string& path, const std::vector<View3DPanel>& views, const View3DOptions& options) const;

  /// Everything recorded, world space (for tests and other renderers).
  struct Triangle3 {
    std::array<Vec3, 3> corners;
    DrawRole role;
    std::optional<Color> fill{};  ///< its own colour (opaque), else the role's
  };
  struct Stroke3 {
    Vec3 a, b;
    DrawRole role;
    bool arrow;  ///< a head at b
  };
  struct Point3 {
    Vec3 p;
    DrawRole role;
  };
  [[nodiscard]] const std::vector<Triangle3>& triangles() const noexcept { return triangles_; }
  [[nodiscard]] const std::vector<Stroke3>& strokes() const noexcept { return strokes_; }
  [[nodiscard]] const std::vector<Point3>& points() const noexcept { return points_; }
  /// The roles drawn, in DrawRole order (what the legend lists).
  [[nodiscard]] std::vector<DrawRole> roles() const;

 private:
  std::vector<Triangle3> triangles_;
  std::vector<Stroke3> strokes_;
  std::vector<Point3> points_;
  std::array<bool, kDrawRoleCount> used_{};
  std::array<std::string, kDrawRoleCount> names_{};
};

}  // namespace collide
