// 3D pictures (draw/view3d): the camera's projection against the pinhole formula, framing that
// keeps a box in view and no farther than needed, and renders read back pixel by pixel: the
// nearer solid wins whatever the drawing order, cutaway and sections drop what they should,
// strokes behind a surface are faint, the legend names the roles drawn; bad options are errors.
#include <collide/draw/palette.hpp>
#include <collide/draw/view3d.hpp>

#include <collide/core/error.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <optional>
#include <vector>
#include <string>

namespace collide {
namespace {

constexpr int kW = 320;
constexpr int kH = 200;

struct Rgb {
  int r, g, b;
};
Rgb rgb(std::uint32_t argb) {
  return {static_cast<int>((argb >> 16) & 0xffu), static_cast<int>((argb >> 8) & 0xffu), static_cast<int>(argb & 0xffu)};
}

/// A camera at +z looking at the origin, y up.
Camera3 front_camera() {
  Camera3 c;
  c.eye = Vec3(0.0f, 0.0f, 10.0f);
  c.target = Vec3(0.0f);
  return c;
}

/// The pixel (picture coordinates) where a world point lands in the picture's only view.
std::array<int, 2> pixel_of(const View3DImage& image, const Camera3& camera, Vec3 p) {
  const auto& v = image.views.at(0);
  const auto at = project(camera, v[2], v[3], p);
  EXPECT_TRUE(at.has_value());
  return {v[0] + static_cast<int>(at->pixel.x), v[1] + static_cast<int>(at->pixel.y)};
}

View3DOptions plain() {
  View3DOptions o;
  o.width = kW + 200;
  o.view_height = kH;
  o.legend = false;
  return o;
}

/// A square of side 2 s in the plane z = z, counter-clockwise seen from +z.
void square(Picture3D& p, float s, float z, DrawRole role, bool facing_plus_z = true) {
  const Vec3 a(-s, -s, z), b(s, -s, z), c(s, s, z), d(-s, s, z);
  if (facing_plus_z) {
    p.draw_triangle(a, b, c, role);
    p.draw_triangle(a, c, d, role);
  } else {
    p.draw_triangle(a, c, b, role);
    p.draw_triangle(a, d, c, role);
  }
}

TEST(View3D, ProjectionIsThePinholeFormula) {
  const Camera3 c = front_camera();
  const float focal = 0.5f * kH / std::tan(0.5f * c.fov_y);
  const auto centre = project(c, kW, kH, Vec3(0.0f));
  ASSERT_TRUE(centre);
  EXPECT_NEAR(centre->pixel.x, 0.5f * kW, 1e-3f);
  EXPECT_NEAR(centre->pixel.y, 0.5f * kH, 1e-3f);
  EXPECT_NEAR(centre->depth, 10.0f, 1e-4f);
  const auto p = project(c, kW, kH, Vec3(1.0f, 2.0f, 4.0f));  // depth 6
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->pixel.x, 0.5f * kW + focal * 1.0f / 6.0f, 1e-3f);  // right is +x
  EXPECT_NEAR(p->pixel.y, 0.5f * kH - focal * 2.0f / 6.0f, 1e-3f);  // up is up the picture
  EXPECT_NEAR(p->depth, 6.0f, 1e-4f);
  EXPECT_FALSE(project(c, kW, kH, Vec3(0.0f, 0.0f, 11.0f)));  // behind the eye
}

TEST(View3D, FramingKeepsEveryCornerInViewAndComesAsCloseAsThat) {
  const Aabb3 box{Vec3(-3.0f, 0.0f, -90.0f), Vec3(49.0f, 40.0f, 9.0f)};
  for (const float az : {0.0f, 0.6f, 2.0f, -1.3f}) {
    for (const float el : {0.1f, 0.6f, 1.2f, 0.5f * std::numbers::pi_v<float>}) {
      for (const float aspect : {1.0f, 1.6f, 3.0f}) {
        SCOPED_TRACE(std::to_string(az) + " " + std::to_string(el) + " " + std::to_string(aspect));
        const Camera3 c = camera_framing(box, az, el, 1.0f, kDefaultFovY, aspect);
        const int h = 400, w = static_cast<int>(aspect * h);
        float slack = 1.0f;  // the smallest distance of a corner to the border, a fraction of the view
        for (int i = 0; i < 8; ++i) {
          const Vec3 corner{(i & 1) ? box.max.x : box.min.x, (i & 2) ? box.max.y : box.min.y, (i & 4) ? box.max.z : box.min.z};
          const auto p = project(c, w, h, corner);
          ASSERT_TRUE(p);
          EXPECT_GE(p->pixel.x, 0.0f);
          EXPECT_LE(p->pixel.x, static_cast<float>(w));
          EXPECT_GE(p->pixel.y, 0.0f);
          EXPECT_LE(p->pixel.y, static_cast<float>(h));
          slack = std::min({slack, p->pixel.x / w, 1.0f - p->pixel.x / w, p->pixel.y / h, 1.0f - p->pixel.y / h});
        }
        EXPECT_LT(slack, 0.05f);  // a corner near the border: no farther than needed
        const auto centre = project(c, w, h, 0.5f * (box.min + box.max));
        ASSERT_TRUE(centre);
        EXPECT_NEAR(centre->pixel.x, 0.5f * w, 0.5f);
        EXPECT_NEAR(centre->pixel.y, 0.5f * h, 0.5f);
      }
    }
  }
}

TEST(View3D, TheNearerSolidWinsWhateverTheOrder) {
  for (const bool body_first : {false, true}) {
    Picture3D p;
    if (body_first) square(p, 1.0f, 1.0f, DrawRole::body);
    square(p, 3.0f, -2.0f, DrawRole::static_geometry);
    if (!body_first) square(p, 1.0f, 1.0f, DrawRole::body);
    const Camera3 cam = front_camera();
    const View3DImage image = p.render({{cam, ""}}, plain());
    const auto centre = pixel_of(image, cam, Vec3(0.0f, 0.0f, 1.0f));
    const Rgb body = rgb(image.at(centre[0], centre[1]));
    EXPECT_GT(body.b, body.r + 40) << "the body is blue, in front";
    const auto level = pixel_of(image, cam, Vec3(2.0f, 2.0f, -2.0f));
    const Rgb grey = rgb(image.at(level[0], level[1]));
    EXPECT_NEAR(grey.r, grey.b, 3) << "the level is grey behind";
    EXPECT_LT(grey.r, 250);
    const auto outside = pixel_of(image, cam, Vec3(4.5f, 0.0f, -2.0f));
    EXPECT_EQ(image.at(outside[0], outside[1]), 0xffffffffu) << "background beyond the level";
  }
}

// A close-up cuts away what is nearer than its cut (run3d: bodies between the camera and the
// character): a body 9 units from the eye hides the level 12 away, until the cut is at 10.
TEST(View3D, CutNearerSeesThroughWhatIsInFrontOfIt) {
  Picture3D p;
  square(p, 1.0f, 1.0f, DrawRole::body);
  square(p, 3.0f, -2.0f, DrawRole::static_geometry);
  const Camera3 cam = front_camera();
  const View3DImage plain_view = p.render({{cam, ""}}, plain());
  View3DPanel cut{cam, ""};
  cut.cut_nearer = 10.0f;
  const View3DImage cut_view = p.render({cut}, plain());
  const auto centre = pixel_of(plain_view, cam, Vec3(0.0f, 0.0f, 1.0f));
  const Rgb before = rgb(plain_view.at(centre[0], centre[1]));
  const Rgb after = rgb(cut_view.at(centre[0], centre[1]));
  EXPECT_GT(before.b, before.r + 40) << "the body, in front";
  EXPECT_NEAR(after.r, after.b, 3) << "the level behind it, once the body is cut away";
  EXPECT_LT(after.r, 250);
  cut.cut_nearer = -1.0f;
  EXPECT_THROW((void)p.render({cut}, plain()), InvalidInput);
}

TEST(View3D, CutawayDropsLevelFacesTurnedAwayButNeverBodies) {
  const Camera3 cam = front_camera();
  for (const DrawRole role : {DrawRole::static_geometry, DrawRole::body}) {
    Picture3D p;
    square(p, 2.0f, 0.0f, role, /*facing_plus_z=*/false);  // turned away from the camera
    for (const bool cutaway : {true, false}) {
      View3DOptions o = plain();
      o.cutaway = cutaway;
      const View3DImage image = p.render({{cam, ""}}, o);
      const auto centre = pixel_of(image, cam, Vec3(0.5f, 0.5f, 0.0f));
      const bool drawn = image.at(centre[0], centre[1]) != 0xffffffffu;
      EXPECT_EQ(drawn, role == DrawRole::body || !cutaway) << to_string(role) << " cutaway " << cutaway;
    }
  }
}

TEST(View3D, ASectionCutsTheLevelAboveItsHeightOnly) {
  // A wall in the plane z = 0 from y = -2 to 2, cut at y = 0.5; a body above the cut stays.
  Picture3D p;
  square(p, 2.0f, 0.0f, DrawRole::static_geometry);
  p.draw_triangle(Vec3(-0.3f, 1.2f, 1.0f), Vec3(0.3f, 1.2f, 1.0f), Vec3(0.0f, 1.8f, 1.0f), DrawRole::body);
  Camera3 cam = front_camera();
  View3DPanel panel{cam, "", 0.5f};
  const View3DImage image = p.render({panel}, plain());
  const auto below = pixel_of(image, cam, Vec3(-1.0f, 0.0f, 0.0f));
  const auto above = pixel_of(image, cam, Vec3(-1.0f, 1.0f, 0.0f));
  const auto body = pixel_of(image, cam, Vec3(0.0f, 1.4f, 1.0f));
  EXPECT_NE(image.at(below[0], below[1]), 0xffffffffu);
  EXPECT_EQ(image.at(above[0], above[1]), 0xffffffffu);
  const Rgb b = rgb(image.at(body[0], body[1]));
  EXPECT_GT(b.b, b.r + 40);
}

TEST(View3D, StrokesBehindASurfaceAreFaint) {
  // A laser along x at z = -1, half of it behind a square at z = 0 covering x < 0.
  Picture3D p;
  p.draw_triangle(Vec3(-4.0f, -2.0f, 0.0f), Vec3(0.0f, -2.0f, 0.0f), Vec3(0.0f, 2.0f, 0.0f), DrawRole::static_geometry);
  p.draw_triangle(Vec3(-4.0f, -2.0f, 0.0f), Vec3(0.0f, 2.0f, 0.0f), Vec3(-4.0f, 2.0f, 0.0f), DrawRole::static_geometry);
  p.draw_segment(Vec3(-3.0f, 0.0f, -1.0f), Vec3(3.0f, 0.0f, -1.0f), DrawRole::laser);
  const Camera3 cam = front_camera();
  const View3DImage image = p.render({{cam, ""}}, plain());
  const auto seen = pixel_of(image, cam, Vec3(1.5f, 0.0f, -1.0f));
  const auto hidden = pixel_of(image, cam, Vec3(-1.5f, 0.0f, -1.0f));
  const Rgb s = rgb(image.at(seen[0], seen[1]));
  const Rgb h = rgb(image.at(hidden[0], hidden[1]));
  EXPECT_GT(s.r - s.g, 100) << "laser red where in view";
  EXPECT_LT(h.r - h.g, (s.r - s.g) / 2) << "faint behind the square";
  // Hidden parts are dashed: along the hidden half, some pixels show the square's grey alone.
  int grey = 0;
  for (float x = -2.8f; x < -0.2f; x += 0.05f) {
    const auto q = pixel_of(image, cam, Vec3(x, 0.0f, -1.0f));
    const Rgb c = rgb(image.at(q[0], q[1]));
    grey += std::abs(c.r - c.g) < 10 ? 1 : 0;
  }
  EXPECT_GT(grey, 3);
}

TEST(View3D, LegendListsTheRolesDrawnAndThePictureIsThatTall) {
  Picture3D p;
  square(p, 1.0f, 0.0f, DrawRole::body);
  p.draw_point(Vec3(0.0f), DrawRole::contact_point);
  p.draw_arrow(Vec3(0.0f), Vec3(0.0f, 1.0f, 0.0f), DrawRole::contact_normal);
  EXPECT_EQ(p.roles(), (std::vector<DrawRole>{DrawRole::body, DrawRole::contact_point, DrawRole::contact_normal}));
  View3DOptions with = plain();
  with.legend = true;
  with.title = "a title";
  const Camera3 cam = front_camera();
  const View3DImage a = p.render({{cam, ""}}, plain());
  const View3DImage b = p.render({{cam, "a view"}, {cam, "another"}}, with);
  EXPECT_EQ(a.width, kW + 200);
  EXPECT_EQ(a.views.size(), 1u);
  EXPECT_EQ(b.views.size(), 2u);
  EXPECT_GT(b.height, a.height);  // a title line, view titles and a legend row
  EXPECT_EQ(b.views[0][3], kH);
  EXPECT_LT(b.views[0][0] + b.views[0][2], b.views[1][0]);  // side by side, apart
  // Every pixel under the legend row's text band is drawn inside the picture.
  EXPECT_EQ(b.pixels.size(), static_cast<std::size_t>(b.width) * static_cast<std::size_t>(b.height));
}

/// A rectangle x in [x0, x1], y in [-1, 1] at depth plane z, facing +z, optionally in its own colour.
void panel_rect(Picture3D& p, float x0, float x1, float z, DrawRole role, std::optional<Color> fill) {
  const Vec3 a(x0, -1.0f, z), b(x1, -1.0f, z), c(x1, 1.0f, z), d(x0, 1.0f, z);
  if (fill) {
    p.draw_triangle(a, b, c, role, *fill);
    p.draw_triangle(a, c, d, role, *fill);
  } else {
    p.draw_triangle(a, b, c, role);
    p.draw_triangle(a, c, d, role);
  }
}

// Things of one role told apart by colour (decompose's hulls): each fill shows, shaded as the
// role's would be, and two colours meeting at the same depth are outlined where one role alone
// is not (the seam between two rectangles 0.1 apart in depth is no depth jump).
TEST(View3D, OwnColoursFillTrianglesAndAreOutlinedWhereTheyMeet) {
  const Camera3 cam = front_camera();
  const Color red{220, 40, 40, 255}, green{40, 200, 40, 0};  // the fill's alpha is not used
  const auto brightness = [](std::uint32_t c) { const Rgb v = rgb(c); return v.r + v.g + v.b; };
  int seam_colours = 0, seam_role = 0, inside_colours = 0, inside_role = 0;
  for (const bool coloured : {true, false}) {
    Picture3D p;
    panel_rect(p, -2.0f, 0.0f, 0.0f, DrawRole::body, coloured ? std::optional<Color>(red) : std::nullopt);
    panel_rect(p, 0.0f, 2.0f, 0.1f, DrawRole::body, coloured ? std::optional<Color>(green) : std::nullopt);
    EXPECT_EQ(p.roles(), std::vector<DrawRole>{DrawRole::body});
    const View3DImage image = p.render({{cam, ""}}, plain());
    const auto left = pixel_of(image, cam, Vec3(-1.0f, 0.0f, 0.0f));
    const auto right = pixel_of(image, cam, Vec3(1.0f, 0.0f, 0.1f));
    const Rgb l = rgb(image.at(left[0], left[1])), r = rgb(image.at(right[0], right[1]));
    if (coloured) {
      EXPECT_GT(l.r, l.g + 60) << "red on the left";
      EXPECT_GT(r.g, r.r + 60) << "green on the right";
    } else {
      EXPECT_GT(l.b, l.r + 40) << "the body's blue";
      EXPECT_NEAR(l.r, r.r, 3) << "one role, one colour (the light at the eye differs a little)";
      EXPECT_NEAR(l.b, r.b, 3);
    }
    // The darkest pixel of the row across the seam, against the rectangles' inside.
    const auto seam = pixel_of(image, cam, Vec3(0.0f, 0.0f, 0.0f));
    int darkest = 3 * 255;
    for (int x = seam[0] - 2; x <= seam[0] + 2; ++x) darkest = std::min(darkest, brightness(image.at(x, seam[1])));
    const int inside = std::min(brightness(image.at(left[0], left[1])), brightness(image.at(right[0], right[1])));
    (coloured ? seam_colours : seam_role) = darkest;
    (coloured ? inside_colours : inside_role) = inside;
  }
  EXPECT_LT(seam_colours, 0.85 * inside_colours) << "two colours meet: an outline";
  EXPECT_GE(seam_role, inside_role - 3) << "one role without colours: no outline at the seam";
}

// Panels of one picture show different roles (decompose: the input mesh beside its hulls), the
// strokes and points of a role too; the legend still names every role drawn.
TEST(View3D, APanelShowsOnlyTheRolesItNames) {
  Picture3D p;
  square(p, 1.0f, 0.0f, DrawRole::static_geometry);
  square(p, 1.0f, 1.0f, DrawRole::body);
  p.draw_segment(Vec3(-3.0f, 1.5f, 2.0f), Vec3(3.0f, 1.5f, 2.0f), DrawRole::laser);
  const Camera3 cam = front_camera();
  View3DPanel level{cam, "level"}, bodies{cam, "bodies"}, all{cam, "all"};
  level.roles = {DrawRole::static_geometry};
  bodies.roles = {DrawRole::body, DrawRole::laser};
  View3DOptions o = plain();
  o.width = 3 * kW;
  const View3DImage image = p.render({level, bodies, all}, o);
  ASSERT_EQ(image.views.size(), 3u);
  const auto at = [&](int view, Vec3 world) {
    const auto& v = image.views[static_cast<std::size_t>(view)];
    const auto s = project(cam, v[2], v[3], world);
    return rgb(image.at(v[0] + static_cast<int>(s->pixel.x), v[1] + static_cast<int>(s->pixel.y)));
  };
  const Rgb level_centre = at(0, Vec3(0.0f)), bodies_centre = at(1, Vec3(0.0f, 0.0f, 1.0f)), all_centre = at(2, Vec3(0.0f, 0.0f, 1.0f));
  EXPECT_NEAR(level_centre.r, level_centre.b, 3) << "the level alone: grey, the body in front not drawn";
  EXPECT_LT(level_centre.r, 250);
  EXPECT_GT(bodies_centre.b, bodies_centre.r + 40) << "the body";
  EXPECT_GT(all_centre.b, all_centre.r + 40) << "every role: the body in front";
  // The laser: red in the second and third views, nothing in the first.
  const Rgb laser_level = at(0, Vec3(2.5f, 1.5f, 2.0f)), laser_bodies = at(1, Vec3(2.5f, 1.5f, 2.0f));
  EXPECT_EQ(laser_level.r + laser_level.g + laser_level.b, 3 * 255) << "no laser where only the level is shown";
  EXPECT_GT(laser_bodies.r, laser_bodies.g + 60) << "the laser";
  // The empty one: a panel of a role that was never drawn shows the background alone.
  View3DPanel none{cam, "none"};
  none.roles = {DrawRole::sensor};
  const View3DImage empty = p.render({none}, plain());
  const auto& v = empty.views[0];
  int ink = 0;
  for (int y = v[1] + 2; y < v[1] + v[3] - 2; ++y) {
    for (int x = v[0] + 2; x < v[0] + v[2] - 2; ++x) ink += empty.at(x, y) != 0xffffffffu;
  }
  EXPECT_EQ(ink, 0);
}

TEST(View3D, DistinctColoursAreOpaqueDifferentAndNeighboursFarApart) {
  std::vector<Color> seen;
  for (int i = 0; i < 1024; ++i) {
    const Color c = distinct_color(i);
    EXPECT_EQ(c.a, 255);
    for (const Color& other : seen) ASSERT_FALSE(other == c) << "index " << i;
    if (!seen.empty()) {
      const Color& b = seen.back();
      const double d = std::hypot(double(c.r) - b.r, double(c.g) - b.g, double(c.b) - b.b);
      EXPECT_GT(d, 100.0) << "indices " << i - 1 << " and " << i;
    }
    seen.push_back(c);
  }
  EXPECT_TRUE(distinct_color(-5) == distinct_color(-5));
}

TEST(View3D, WritesAPngOfItsSizeAndNamesAPathItCannotWrite) {
  Picture3D p;
  square(p, 1.0f, 0.0f, DrawRole::body);
  const std::string path = ::testing::TempDir() + "view3d_test.png";
  std::remove(path.c_str());
  const Camera3 cam = front_camera();
  p.write_png(path, {{cam, "view"}}, plain());
  std::ifstream in(path, std::ios::binary);
  std::array<unsigned char, 24> head{};
  in.read(reinterpret_cast<char*>(head.data()), head.size());
  ASSERT_TRUE(in.good());
  EXPECT_EQ(head[1], 'P');
  EXPECT_EQ(head[2], 'N');
  EXPECT_EQ(head[3], 'G');
  // IHDR: width and height, big-endian, at bytes 16 and 20.
  const auto be = [&](int at) {
    return (head[at] << 24) | (head[at + 1] << 16) | (head[at + 2] << 8) | head[at + 3];
  };
  const View3DImage image = p.render({{cam, "view"}}, plain());
  EXPECT_EQ(be(16), image.width);
  EXPECT_EQ(be(20), image.height);
  try {
    p.write_png("/nonexistent/dir/x.png", {{cam, ""}}, plain());
    FAIL() << "wrote into a missing folder";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/x.png"), std::string::npos) << e.what();
  }
}

// Titles come from file names and user input, which need not be UTF-8: Cairo stops drawing on
// ill-formed text, so the view cleans it (picture_font.hpp) and the legend still appears.
TEST(View3D, TitlesThatAreNotUtf8StillDrawTheWholePicture) {
  Picture3D p;
  square(p, 1.0f, 0.0f, DrawRole::body);
  View3DOptions o = plain();
  o.legend = true;
  o.title = "level \xff\xfe.obj \xc3";
  const Camera3 cam = front_camera();
  const View3DImage bad = p.render({{cam, "view \x80"}}, o);
  o.title = "level ??.obj ?";
  const View3DImage good = p.render({{cam, "view ?"}}, o);
  ASSERT_EQ(bad.height, good.height);
  // The legend row (below the view) has ink in both pictures: drawing did not stop at the title.
  const auto ink_below_view = [](const View3DImage& im) {
    int ink = 0;
    for (int y = im.views[0][1] + im.views[0][3] + 1; y < im.height; ++y) {
      for (int x = 0; x < im.width; ++x) ink += (im.pixels[std::size_t(y) * std::size_t(im.width) + std::size_t(x)] & 0xffffffu) != 0xffffffu;
    }
    return ink;
  };
  EXPECT_GT(ink_below_view(bad), 20);
  EXPECT_GT(ink_below_view(good), 20);
}

TEST(View3D, BadOptionsAndCamerasAreErrors) {
  Picture3D p;
  square(p, 1.0f, 0.0f, DrawRole::body);
  const Camera3 cam = front_camera();
  View3DOptions narrow = plain();
  narrow.width = 10;
  EXPECT_THROW((void)p.render({{cam, ""}}, narrow), InvalidInput);
  View3DOptions huge = plain();
  huge.view_height = kMaxViewSide + 1;
  EXPECT_THROW((void)p.render({{cam, ""}}, huge), InvalidInput);
  EXPECT_THROW((void)p.render({}, plain()), InvalidInput);
  Camera3 same = cam;
  same.target = same.eye;
  EXPECT_THROW((void)p.render({{same, ""}}, plain()), InvalidInput);
  Camera3 along = cam;
  along.up = Vec3(0.0f, 0.0f, 1.0f);
  EXPECT_THROW((void)p.render({{along, ""}}, plain()), InvalidInput);
  Camera3 nan = cam;
  nan.eye.x = std::nanf("");
  EXPECT_THROW((void)p.render({{nan, ""}}, plain()), InvalidInput);
  Camera3 wide = cam;
  wide.fov_y = 3.2f;
  EXPECT_THROW((void)p.render({{wide, ""}}, plain()), InvalidInput);
}

}  // namespace
}  // namespace collide
