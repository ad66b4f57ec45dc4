#include "picture_font.hpp"

#include <collide/draw/cairo_picture.hpp>
#include <collide/draw/palette.hpp>
#include <collide/draw/view3d.hpp>

#include <collide/core/error.hpp>

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <memory>
#include <string>
#include <utility>

namespace collide {

namespace {

// ---- shading and outlines ---------------------------------------------------------------------

/// Light on a solid: ambient, plus a sun from above (world y) and slightly aside, plus a light
/// at the eye (so faces seen edge-on by the sun still read). Weights of the three.
constexpr float kAmbient = 0.38f;
constexpr float kSunWeight = 0.42f;
constexpr float kHeadlightWeight = 0.28f;
/// The sun's direction (towards it), world space, normalised where used.
constexpr Vec3 kSunDirection{0.35f, 1.0f, 0.55f};
/// A pixel beside a nearer one whose depth is smaller by more than this fraction of its own, or
/// beside a solid of another role, is darkened to this fraction: the silhouettes' outlines.
constexpr float kOutlineDepthJump = 0.03f;
constexpr float kOutlineShade = 0.45f;
/// camera_framing leaves this much room around the box (a factor on the distance).
constexpr float kFramingMargin = 1.06f;
/// Near plane, a fraction of the camera's distance to its target.
constexpr float kNearFraction = 1e-4f;

// ---- strokes and points over the render -------------------------------------------------------

/// A stroke or point counts as in view where its depth is within this fraction of the
/// farthest surface sample at its pixel (it lies on that surface: a hit point, a contact).
constexpr float kDepthBias = 0.01f;
/// Parts behind a surface: drawn with this opacity, dashed.
constexpr float kHiddenAlpha = 0.3f;
/// Strokes are tested against the depth buffer every this many pixels along their length.
constexpr float kStrokeSampleStep = 1.5f;
/// Most samples along one stroke (a stroke across the whole picture at its largest size).
constexpr int kMaxStrokeSamples = 2 * kMaxViewSide;

// ---- layout -------------------------------------------------------------------------------------

/// The palette's sizes (pixels for 2D pictures about 700 wide) are multiplied by the picture's
/// width over this, within [1, kMaxUnit].
constexpr float kUnitWidth = 700.0f;
constexpr float kMaxUnit = 6.0f;
/// Text size, padding around the picture, gap between views and between legend entries, the
/// legend's swatch side: in units (above).
constexpr double kFontSize = 7.0;
constexpr double kPadding = 5.0;
constexpr double kViewGap = 6.0;
constexpr double kLegendGap = 9.0;
constexpr double kSwatchSide = 6.0;
/// A line of text is this many times the font size tall.
constexpr double kLineHeight = 1.5;
/// Points: the palette's point size (pixels) times this, in units.
constexpr double kPointScale = 0.5;
/// Arrow heads: length and half width at the base, in units.
constexpr double kViewArrowHead = 5.0;
constexpr double kViewArrowHalfWidth = 2.2;

constexpr std::uint32_t kBackgroundArgb = 0xffffffffu;

std::uint32_t argb(Color c, float shade) noexcept {
  const auto ch = [&](std::uint8_t v) {
    return static_cast<std::uint32_t>(std::clamp(static_cast<float>(v) * shade + 0.5f, 0.0f, 255.0f));
  };
  return 0xff000000u | (ch(c.r) << 16) | (ch(c.g) << 8) | ch(c.b);
}

/// The colour a role's solids are filled with (opaque: the render has no translucency).
Color solid_color(DrawRole role) noexcept {
  const DrawStyle& s = draw_style(role);
  return s.fill.a > 0 ? s.fill : s.stroke;
}

/// `c` with its opacity multiplied by `alpha` in [0, 1] (lines behind a surface are faint).
Color faded(Color c, float alpha) noexcept {
  c.a = static_cast<std::uint8_t>(std::clamp(static_cast<float>(c.a) * alpha + 0.5f, 0.0f, 255.0f));
  return c;
}

/// The camera's frame: unit right, up and forward vectors, and the focal length in pixels.
struct CameraFrame {
  Vec3 eye, right, up, forward;
  float focal = 1.0f;  ///< pixels
  float cx = 0.0f, cy = 0.0f;
  float near = 0.0f;

  /// `cut_nearer`: View3DPanel::cut_nearer (the near plane, when further than the default).
  CameraFrame(const Camera3& c, int width, int height, std::optional<float> cut_nearer = std::nullopt) {
    eye = c.eye;
    forward = normalize(c.target - c.eye);
    right = normalize(cross(forward, c.up));
    up = cross(right, forward);
    focal = 0.5f * static_cast<float>(height) / std::tan(0.5f * c.fov_y);
    cx = 0.5f * static_cast<float>(width);
    cy = 0.5f * static_cast<float>(height);
    near = kNearFraction * length(c.target - c.eye);
    if (cut_nearer && *cut_nearer > near) near = *cut_nearer;
  }
  [[nodiscard]] Vec3 to_view(Vec3 p) const noexcept {
    const Vec3 d = p - eye;
    return {dot(d, right), dot(d, up), dot(d, forward)};
  }
  /// Pixel x, y and 1 / depth of a view-space point in front of the near plane.
  [[nodiscard]] Vec3 to_screen(Vec3 v) const noexcept {
    const float iz = 1.0f / v.z;
    return {cx + focal * v.x * iz, cy - focal * v.y * iz, iz};
  }
};

void check_camera(const Camera3& c) {
  const bool finite = is_finite(c.eye) && is_finite(c.target) && is_finite(c.up) && std::isfinite(c.fov_y);
  if (!finite) throw InvalidInput("3D view: camera not finite");
  const Vec3 d = c.target - c.eye;
  if (!(length(d) > 0.0f)) throw InvalidInput("3D view: camera eye and target coincide");
  if (!(length(cross(d, c.up)) > 1e-6f * length(d) * length(c.up))) {
    throw InvalidInput("3D view: camera up is zero or along the view direction");
  }
  if (!(c.fov_y > 0.0f && c.fov_y < std::numbers::pi_v<float>)) {
    throw InvalidInput("3D view: field of view must be in (0, pi) radians");
  }
}

/// What a sample's outline compares: the role of the nearest solid and the colour it is filled
/// with (its role's, or its own: Picture3D::draw_triangle with a fill), so solids of another role
/// or another colour are outlined where they meet.
std::uint32_t surface_key(DrawRole role, Color fill) noexcept {
  return (static_cast<std::uint32_t>(fill.r) << 24 | static_cast<std::uint32_t>(fill.g) << 16 |
          static_cast<std::uint32_t>(fill.b) << 8) | static_cast<std::uint32_t>(role);
}

/// One view's render at kViewSupersample times its size: colour, 1 / depth (0: nothing) and
/// the surface (surface_key) of the nearest solid per sample.
struct Raster {
  int width = 0, height = 0;
  std::vector<std::uint32_t> color;
  std::vector<float> inv_depth;
  std::vector<std::uint32_t> role;
  static constexpr std::uint32_t kNoRole = 0xffffffffu;  // never a key: roles are below 0xff

  Raster(int w, int h)
      : width(w), height(h), color(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), kBackgroundArgb),
        inv_depth(color.size(), 0.0f), role(color.size(), kNoRole) {}

  /// A screen-space triangle (pixel x, y, 1 / depth per corner), depth-tested.
  void fill(const Vec3& a, const Vec3& b, const Vec3& c, std::uint32_t argb_color, std::uint32_t role_id) {
    const float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (!(std::fabs(area) > 0.0f)) return;
    const float inv_area = 1.0f / area;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}))));
    const int x1 = std::min(width - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}))));
    const int y1 = std::min(height - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}))));
    for (int y = y0; y <= y1; ++y) {
      const float py = static_cast<float>(y) + 0.5f;
      for (int x = x0; x <= x1; ++x) {
        const float px = static_cast<float>(x) + 0.5f;
        // Barycentric weights from the edge functions, the same sign as the area inside.
        const float w0 = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) * inv_area;
        const float w1 = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) * inv_area;
        const float w2 = 1.0f - w0 - w1;
        if (w0 < 0.0f || w1 < 0.0f || w2 < 0.0f) continue;
        const float iz = w0 * a.z + w1 * b.z + w2 * c.z;  // 1 / depth is linear on the screen
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
        if (iz <= inv_depth[i]) continue;
        inv_depth[i] = iz;
        color[i] = argb_color;
        role[i] = role_id;
      }
    }
  }

  /// Darkens samples beside a nearer solid (by a depth jump or another role): outlines.
  void outline() {
    std::vector<std::uint8_t> mark(color.size(), 0);
    const auto nearer = [&](std::size_t i, std::size_t j) {  // is sample j an edge over sample i?
      if (role[j] == kNoRole) return false;
      if (role[i] == kNoRole) return true;
      if (inv_depth[j] <= inv_depth[i]) return false;
      // Depths from their inverses: jump relative to the nearer one.
      const float zi = 1.0f / inv_depth[i], zj = 1.0f / inv_depth[j];
      return zi - zj > kOutlineDepthJump * zj || role[i] != role[j];
    };
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
        if ((x > 0 && nearer(i, i - 1)) || (x + 1 < width && nearer(i, i + 1)) ||
            (y > 0 && nearer(i, i - static_cast<std::size_t>(width))) ||
            (y + 1 < height && nearer(i, i + static_cast<std::size_t>(width)))) {
          mark[i] = 1;
        }
      }
    }
    for (std::size_t i = 0; i < color.size(); ++i) {
      if (mark[i] == 0) continue;
      const std::uint32_t c = color[i];
      const auto dark = [&](int shift) {
        return static_cast<std::uint32_t>(static_cast<float>((c >> shift) & 0xffu) * kOutlineShade) << shift;
      };
      color[i] = 0xff000000u | dark(16) | dark(8) | dark(0);
    }
  }
};

/// A polygon clipped to the side of a plane where `side(p)` >= 0 (`side` linear in p; Sutherland
/// & Hodgman 1974, one plane): up to one more corner than it had.
template <class Side>
int clip_polygon(const Vec3* in, int n, Side&& side, Vec3* out) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3& p = in[i];
    const Vec3& q = in[(i + 1) % n];
    const float sp = side(p), sq = side(q);
    if (sp >= 0.0f) out[m++] = p;
    if ((sp >= 0.0f) != (sq >= 0.0f)) out[m++] = p + sp / (sp - sq) * (q - p);
  }
  return m;
}

/// Cairo objects with their owners.
struct SurfaceDeleter {
  void operator()(cairo_surface_t* s) const noexcept { cairo_surface_destroy(s); }
};
struct ContextDeleter {
  void operator()(cairo_t* c) const noexcept { cairo_destroy(c); }
};
using Surface = std::unique_ptr<cairo_surface_t, SurfaceDeleter>;
using Context = std::unique_ptr<cairo_t, ContextDeleter>;

/// The legend's entries laid out in rows within `width`: each entry's left x and its row.
struct LegendLayout {
  std::vector<std::pair<double, int>> places;
  int rows = 0;
};
LegendLayout layout_legend(const TextMeasurer& measure, const std::vector<std::string>& names, double left, double width,
                           double unit) {
  LegendLayout l;
  double x = left;
  int row = 0;
  for (const std::string& name : names) {
    const double w = kSwatchSide * unit + 0.6 * kFontSize * unit + measure.width(name);
    if (x > left && x + w > left + width) {
      x = left;
      ++row;
    }
    l.places.emplace_back(x, row);
    x += w + kLegendGap * unit;
  }
  l.rows = names.empty() ? 0 : row + 1;
  return l;
}

}  // namespace

Camera3 camera_framing(const Aabb3& box, float azimuth, float elevation, float zoom, float fov_y, float aspect) {
  const Vec3 center = 0.5f * (box.min + box.max);
  const Vec3 from{std::cos(elevation) * std::sin(azimuth), std::sin(elevation), std::cos(elevation) * std::cos(azimuth)};
  Camera3 c;
  c.target = center;
  c.fov_y = fov_y;
  // Looking straight down or up: the picture's up is -z (north up).
  c.up = std::fabs(from.y) > 0.999f ? Vec3(0.0f, 0.0f, -1.0f) : Vec3(0.0f, 1.0f, 0.0f);
  // The nearest distance at which every corner is in the view: corner offset x, y across the
  // view and z along it needs |x| <= tan(fov_x / 2) (d + z), and as much for y.
  const Vec3 forward = -from;
  const Vec3 right = normalize(cross(forward, c.up));
  const Vec3 up = cross(right, forward);
  const float ty = std::tan(0.5f * fov_y), tx = ty * aspect;
  float distance = 0.0f;
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner{(i & 1) ? box.max.x : box.min.x, (i & 2) ? box.max.y : box.min.y, (i & 4) ? box.max.z : box.min.z};
    const Vec3 d = corner - center;
    distance = std::max(distance, std::max(std::fabs(dot(d, right)) / tx, std::fabs(dot(d, up)) / ty) - dot(d, forward));
  }
  distance = std::max(distance * kFramingMargin, 1e-6f) / std::max(zoom, 1e-6f);
  c.eye = center + distance * from;
  return c;
}

std::optional<ViewPoint> project(const Camera3& camera, int view_width, int view_height, Vec3 p) noexcept {
  const CameraFrame f(camera, view_width, view_height);
  const Vec3 v = f.to_view(p);
  if (!(v.z >= f.near)) return std::nullopt;
  const Vec3 s = f.to_screen(v);
  return ViewPoint{Vec2(s.x, s.y), v.z};
}

void Picture3D::draw_triangle(const Vec3& a, const Vec3& b, const Vec3& c, DrawRole role) {
  triangles_.push_back({{a, b, c}, role});
  used_[static_cast<std::size_t>(role)] = true;
}

void Picture3D::draw_triangle(const Vec3& a, const Vec3& b, const Vec3& c, DrawRole role, Color fill) {
  fill.a = 255;
  triangles_.push_back({{a, b, c}, role, fill});
  used_[static_cast<std::size_t>(role)] = true;
}

void Picture3D::draw_segment(const Vec3& a, const Vec3& b, DrawRole role) {
  strokes_.push_back({a, b, role, false});
  used_[static_cast<std::size_t>(role)] = true;
}

void Picture3D::draw_arrow(const Vec3& from, const Vec3& to, DrawRole role) {
  strokes_.push_back({from, to, role, true});
  used_[static_cast<std::size_t>(role)] = true;
}

void Picture3D::draw_point(const Vec3& p, DrawRole role) {
  points_.push_back({p, role});
  used_[static_cast<std::size_t>(role)] = true;
}

void Picture3D::set_role_name(DrawRole role, std::string name) {
  names_[static_cast<std::size_t>(role)] = std::move(name);
}

std::vector<DrawRole> Picture3D::roles() const {
  std::vector<DrawRole> out;
  for (int r = 0; r < kDrawRoleCount; ++r) {
    if (used_[static_cast<std::size_t>(r)]) out.push_back(static_cast<DrawRole>(r));
  }
  return out;
}

View3DImage Picture3D::render(const std::vector<View3DPanel>& views, const View3DOptions& o) const {
  if (o.width < kMinPictureWidth || o.width > kMaxViewSide) {
    throw InvalidInput("3D view: width " + std::to_string(o.width) + " outside [" + std::to_string(kMinPictureWidth) + ", " +
                       std::to_string(kMaxViewSide) + "]");
  }
  if (o.view_height < 0 || o.view_height > kMaxViewSide) {
    throw InvalidInput("3D view: view height " + std::to_string(o.view_height) + " outside [0, " +
                       std::to_string(kMaxViewSide) + "]");
  }
  if (views.empty()) throw InvalidInput("3D view: no view");
  for (const View3DPanel& v : views) {
    check_camera(v.camera);
    if (v.cut_nearer && !(std::isfinite(*v.cut_nearer) && *v.cut_nearer >= 0.0f)) {
      throw InvalidInput("3D view: cut_nearer " + std::to_string(*v.cut_nearer) + " not finite and >= 0");
    }
  }

  // ---- layout: title, view titles, views side by side, legend ----
  const double unit = std::clamp(static_cast<double>(o.width) / kUnitWidth, 1.0, static_cast<double>(kMaxUnit));
  const double font = kFontSize * unit;
  const double line = kLineHeight * font;
  const double pad = kPadding * unit;
  const int n = static_cast<int>(views.size());
  const double gap = kViewGap * unit;
  const int view_w = static_cast<int>((o.width - 2.0 * pad - (n - 1) * gap) / n);
  if (view_w < 1) throw InvalidInput("3D view: width " + std::to_string(o.width) + " too small for " + std::to_string(n) + " views");
  const int view_h = o.view_height > 0 ? o.view_height
                                       : std::max(1, static_cast<int>(static_cast<float>(view_w) / kDefaultViewAspect));
  const bool view_titles = std::any_of(views.begin(), views.end(), [](const View3DPanel& v) { return !v.title.empty(); });
  std::vector<DrawRole> legend_roles = o.legend ? roles() : std::vector<DrawRole>{};
  std::vector<std::string> legend_names;
  for (const DrawRole r : legend_roles) {
    const std::string& named = names_[static_cast<std::size_t>(r)];
    legend_names.push_back(clean_text(named.empty() ? std::string(to_string(r)) : named));
  }
  const LegendLayout legend = layout_legend(TextMeasurer(font), legend_names, pad, o.width - 2.0 * pad, unit);
  const double top = pad + (o.title.empty() ? 0.0 : line) + (view_titles ? line : 0.0);
  const int height = static_cast<int>(std::ceil(top + view_h + (legend.rows > 0 ? pad + legend.rows * line : 0.0) + pad));
  if (height > kMaxViewSide) throw InvalidInput("3D view: picture height " + std::to_string(height) + " over " + std::to_string(kMaxViewSide));

  const Surface surface(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, o.width, height));
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS) throw InvalidInput("3D view: cannot allocate the picture");
  const Context cr(cairo_create(surface.get()));
  cairo_set_source_rgb(cr.get(), 1.0, 1.0, 1.0);
  cairo_paint(cr.get());
  use_picture_font(cr.get(), font);

  View3DImage image;
  image.width = o.width;
  image.height = height;
  const Vec3 sun = normalize(kSunDirection);
  for (int k = 0; k < n; ++k) {
    const View3DPanel& panel = views[static_cast<std::size_t>(k)];
    const int left = static_cast<int>(pad + k * (view_w + gap));
    const int view_top = static_cast<int>(top);
    image.views.push_back({left, view_top, view_w, view_h});

    // ---- the solids, supersampled ----
    constexpr int S = kViewSupersample;
    Raster raster(view_w * S, view_h * S);
    const CameraFrame frame(panel.camera, view_w * S, view_h * S, panel.cut_nearer);
    const auto shown = [&](DrawRole role) {
      return panel.roles.empty() || std::find(panel.roles.begin(), panel.roles.end(), role) != panel.roles.end();
    };
    for (const Triangle3& t : triangles_) {
      if (!shown(t.role)) continue;
      const Vec3 normal = cross(t.corners[1] - t.corners[0], t.corners[2] - t.corners[0]);
      const float facing = dot(normal, frame.eye - t.corners[0]);
      if (o.cutaway && t.role == DrawRole::static_geometry && facing < 0.0f) continue;
      const float len = length(normal);
      if (!(len > 0.0f)) continue;
      const Vec3 nrm = (facing < 0.0f ? -normal : normal) / len;
      const Vec3 to_eye = normalize(frame.eye - t.corners[0]);
      const float light = kAmbient + kSunWeight * std::max(0.0f, dot(nrm, sun)) +
                          kHeadlightWeight * std::max(0.0f, dot(nrm, to_eye));
      const Color base = t.fill ? *t.fill : solid_color(t.role);
      const std::uint32_t color = argb(base, std::min(light, 1.0f));
      // Cut at the section plane (static geometry), then at the near plane (view space).
      std::array<Vec3, 4> world_corners{t.corners[0], t.corners[1], t.corners[2], Vec3(0.0f)};
      int m = 3;
      if (panel.cut_above && t.role == DrawRole::static_geometry) {
        std::array<Vec3, 4> cut;
        const float h = *panel.cut_above;
        m = clip_polygon(world_corners.data(), 3, [h](const Vec3& p) { return h - p.y; }, cut.data());
        world_corners = cut;
      }
      if (m < 3) continue;
      std::array<Vec3, 4> v;
      for (int i = 0; i < m; ++i) v[static_cast<std::size_t>(i)] = frame.to_view(world_corners[static_cast<std::size_t>(i)]);
      std::array<Vec3, 5> clipped;
      m = clip_polygon(v.data(), m, [&](const Vec3& p) { return p.z - frame.near; }, clipped.data());
      if (m < 3) continue;
      std::array<Vec3, 5> s;
      for (int i = 0; i < m; ++i) s[static_cast<std::size_t>(i)] = frame.to_screen(clipped[static_cast<std::size_t>(i)]);
      for (int i = 1; i + 1 < m; ++i) {
        raster.fill(s[0], s[static_cast<std::size_t>(i)], s[static_cast<std::size_t>(i + 1)], color, surface_key(t.role, base));
      }
    }
    raster.outline();

    // ---- averaged down into the picture ----
    // Per pixel of the view, the farthest sample's 1 / depth (a stroke in front of any sample of
    // the pixel counts as in view).
    std::vector<float> far_inv_depth(static_cast<std::size_t>(view_w) * static_cast<std::size_t>(view_h), 0.0f);
    cairo_surface_flush(surface.get());
    unsigned char* data = cairo_image_surface_get_data(surface.get());
    const int stride = cairo_image_surface_get_stride(surface.get());
    for (int y = 0; y < view_h; ++y) {
      auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(view_top + y) * stride);
      for (int x = 0; x < view_w; ++x) {
        unsigned r = 0, g = 0, b = 0;
        float far = std::numeric_limits<float>::max();
        for (int sy = 0; sy < S; ++sy) {
          for (int sx = 0; sx < S; ++sx) {
            const std::size_t i = static_cast<std::size_t>(y * S + sy) * static_cast<std::size_t>(raster.width) +
                                  static_cast<std::size_t>(x * S + sx);
            const std::uint32_t c = raster.color[i];
            r += (c >> 16) & 0xffu;
            g += (c >> 8) & 0xffu;
            b += c & 0xffu;
            far = std::min(far, raster.inv_depth[i]);
          }
        }
        constexpr unsigned kSamples = S * S;
        row[left + x] = 0xff000000u | ((r / kSamples) << 16) | ((g / kSamples) << 8) | (b / kSamples);
        far_inv_depth[static_cast<std::size_t>(y) * static_cast<std::size_t>(view_w) + static_cast<std::size_t>(x)] = far;
      }
    }
    cairo_surface_mark_dirty(surface.get());

    // ---- strokes and points, in view or behind a surface ----
    const CameraFrame view(panel.camera, view_w, view_h, panel.cut_nearer);
    const auto in_view = [&](const Vec3& s) {  // s: pixel x, y and 1 / depth
      const int x = static_cast<int>(std::floor(s.x)), y = static_cast<int>(std::floor(s.y));
      if (x < 0 || y < 0 || x >= view_w || y >= view_h) return true;
      const float surface_iz = far_inv_depth[static_cast<std::size_t>(y) * static_cast<std::size_t>(view_w) + static_cast<std::size_t>(x)];
      return s.z >= surface_iz * (1.0f - kDepthBias);
    };
    cairo_save(cr.get());
    cairo_rectangle(cr.get(), left, view_top, view_w, view_h);
    cairo_clip(cr.get());
    cairo_translate(cr.get(), left, view_top);
    cairo_set_line_cap(cr.get(), CAIRO_LINE_CAP_ROUND);
    cairo_set_line_join(cr.get(), CAIRO_LINE_JOIN_ROUND);
    for (const Stroke3& st : strokes_) {
      if (!shown(st.role)) continue;
      const DrawStyle& style = draw_style(st.role);
      std::array<Vec3, 2> ends{view.to_view(st.a), view.to_view(st.b)};
      std::array<Vec3, 3> clipped;
      if (clip_polygon(ends.data(), 2, [&](const Vec3& p) { return p.z - view.near; }, clipped.data()) < 2) continue;
      // The two ends as a closed polygon: its first two corners clipped are the part in front.
      const Vec3 a = clipped[0], b = clipped[1];
      const Vec3 sa = view.to_screen(a), sb = view.to_screen(b);
      const float pixels = length(Vec2(sb.x - sa.x, sb.y - sa.y));
      const int samples = std::clamp(static_cast<int>(pixels / kStrokeSampleStep) + 1, 1, kMaxStrokeSamples);
      const double width = style.stroke_width * unit;
      cairo_set_line_width(cr.get(), width);
      // Runs of samples in view or not, each one polyline.
      bool prev_in = in_view(sa);
      cairo_move_to(cr.get(), sa.x, sa.y);
      const auto finish_run = [&](bool visible) {
        if (visible && !style.dashed) {
          cairo_set_dash(cr.get(), nullptr, 0, 0.0);
        } else {
          const double dash[] = {kDashLength * unit, kDashLength * unit};
          cairo_set_dash(cr.get(), dash, 2, 0.0);
        }
        set_source(cr.get(), visible ? style.stroke : faded(style.stroke, kHiddenAlpha));
        cairo_stroke(cr.get());
      };
      for (int i = 1; i <= samples; ++i) {
        const float t = static_cast<float>(i) / static_cast<float>(samples);
        const Vec3 s = view.to_screen(a + t * (b - a));
        const bool now_in = in_view(s);
        cairo_line_to(cr.get(), s.x, s.y);
        if (now_in != prev_in || i == samples) {
          finish_run(prev_in);
          cairo_move_to(cr.get(), s.x, s.y);
          prev_in = now_in;
        }
      }
      if (st.arrow && pixels > 0.0f) {
        // A head at the tip, along the stroke's last stretch on the screen.
        const Vec3 before = view.to_screen(a + (1.0f - std::min(1.0f, 2.0f / std::max(pixels, 1.0f))) * (b - a));
        Vec2 dir(sb.x - before.x, sb.y - before.y);
        if (length(dir) > 0.0f) {
          dir = normalize(dir);
          const double head = std::min(kViewArrowHead * unit, 0.5 * pixels);
          const double half = kViewArrowHalfWidth * unit * head / (kViewArrowHead * unit);
          const Vec2 across(-dir.y, dir.x);
          cairo_set_dash(cr.get(), nullptr, 0, 0.0);
          cairo_move_to(cr.get(), sb.x, sb.y);
          cairo_line_to(cr.get(), sb.x - head * dir.x + half * across.x, sb.y - head * dir.y + half * across.y);
          cairo_line_to(cr.get(), sb.x - head * dir.x - half * across.x, sb.y - head * dir.y - half * across.y);
          cairo_close_path(cr.get());
          set_source(cr.get(), in_view(sb) ? style.stroke : faded(style.stroke, kHiddenAlpha));
          cairo_fill(cr.get());
        }
      }
    }
    cairo_set_dash(cr.get(), nullptr, 0, 0.0);
    for (const Point3& p : points_) {
      if (!shown(p.role)) continue;
      const DrawStyle& style = draw_style(p.role);
      const Vec3 v = view.to_view(p.p);
      if (!(v.z >= view.near)) continue;
      const Vec3 s = view.to_screen(v);
      const double r = style.point_size * unit * kPointScale;
      cairo_new_sub_path(cr.get());
      cairo_arc(cr.get(), s.x, s.y, r, 0.0, 2.0 * std::numbers::pi);
      if (in_view(s)) {
        set_source(cr.get(), style.stroke);
        cairo_fill(cr.get());
      } else {
        set_source(cr.get(), faded(style.stroke, kHiddenAlpha));
        cairo_set_line_width(cr.get(), 0.5 * unit);
        cairo_stroke(cr.get());
      }
    }
    cairo_restore(cr.get());
    // The view's frame and title.
    cairo_set_line_width(cr.get(), 1.0);
    set_source(cr.get(), kPanelFrame);
    cairo_rectangle(cr.get(), left + 0.5, view_top + 0.5, view_w - 1.0, view_h - 1.0);
    cairo_stroke(cr.get());
    if (!panel.title.empty()) {
      set_source(cr.get(), kPictureText);
      cairo_move_to(cr.get(), left, view_top - 0.35 * line);
      cairo_show_text(cr.get(), clean_text(panel.title).c_str());
    }
  }

  // ---- title and legend ----
  if (!o.title.empty()) {
    set_source(cr.get(), kPictureText);
    cairo_move_to(cr.get(), pad, pad + 0.75 * line);
    cairo_show_text(cr.get(), clean_text(o.title).c_str());
  }
  const double legend_top = top + view_h + pad;
  for (std::size_t i = 0; i < legend_roles.size(); ++i) {
    const DrawStyle& style = draw_style(legend_roles[i]);
    const double x = legend.places[i].first;
    const double y = legend_top + legend.places[i].second * line;
    const double side = kSwatchSide * unit;
    const double mid = y + 0.5 * line;
    switch (style.swatch) {
      case Swatch::solid:
        set_source(cr.get(), solid_color(legend_roles[i]));
        cairo_rectangle(cr.get(), x, mid - 0.5 * side, side, side);
        cairo_fill_preserve(cr.get());
        set_source(cr.get(), style.stroke);
        cairo_set_line_width(cr.get(), 1.0);
        cairo_stroke(cr.get());
        break;
      case Swatch::line:
        set_source(cr.get(), style.stroke);
        cairo_set_line_width(cr.get(), style.stroke_width * unit);
        cairo_move_to(cr.get(), x, mid);
        cairo_line_to(cr.get(), x + side, mid);
        cairo_stroke(cr.get());
        break;
      case Swatch::marker:
        set_source(cr.get(), style.stroke);
        cairo_new_sub_path(cr.get());
        cairo_arc(cr.get(), x + 0.5 * side, mid, style.point_size * unit * kPointScale, 0.0, 2.0 * std::numbers::pi);
        cairo_fill(cr.get());
        break;
    }
    set_source(cr.get(), kPictureText);
    cairo_move_to(cr.get(), x + side + 0.6 * font, mid + 0.35 * font);
    cairo_show_text(cr.get(), legend_names[i].c_str());
  }

  cairo_surface_flush(surface.get());
  const unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  image.pixels.resize(static_cast<std::size_t>(o.width) * static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y) {
    const auto* row = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
    std::copy(row, row + o.width, image.pixels.begin() + static_cast<std::ptrdiff_t>(y) * o.width);
  }
  return image;
}

void Picture3D::write_png(const std::string& path, const std::vector<View3DPanel>& views, const View3DOptions& options) const {
  View3DImage image = render(views, options);
  const int stride = cairo_format_stride_for_width(CAIRO_FORMAT_ARGB32, image.width);
  if (stride != 4 * image.width) throw InvalidInput(path + ": unexpected row stride");
  const Surface rendered(cairo_image_surface_create_for_data(reinterpret_cast<unsigned char*>(image.pixels.data()),
                                                             CAIRO_FORMAT_ARGB32, image.width, image.height, stride));
  save_drawing(path, PictureFormat::png, image.width, image.height, [&](cairo_t* cr) {
    cairo_set_source_surface(cr, rendered.get(), 0.0, 0.0);
    cairo_paint(cr);
  });
}

}  // namespace collide
