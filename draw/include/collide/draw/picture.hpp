#pragma once
/// @file
/// A picture: debug geometry recorded through the DebugDraw interface into side-by-side panels,
/// then laid out (world -> image mapping, title, legend) and replayed in image pixels to a
/// renderer (a PixelSink). CairoSink (cairo_picture.hpp) is the renderer: one drawing code for
/// PNG, SVG and PDF files, or any Cairo surface.
///
/// Layout, top to bottom, all in image pixels with u = text_scale: a padding of kPicturePadding
/// u; the title line (if any); the panel titles (if any panel has one); the panels' plot areas
/// side by side, kPanelGap u apart; the legend (one entry per role drawn, in DrawRole order,
/// flowing left to right in rows); the padding again. Text is set in kPictureFontFamily at
/// kFontSizePerTextScale u pixels and measured with Cairo, so titles are cut to fit and legend
/// rows wrap where the real text ends. Each panel shows its world rectangle (given, or fitted to
/// its content plus a margin) centred in its plot area at one uniform scale, y up (mathematics)
/// or y down (screens, Tiled maps).

#include <collide/core/aabb.hpp>
#include <collide/core/debug_draw.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace collide {

/// Largest picture side, pixels: keeps a mistyped size from allocating gigabytes (a PNG of
/// 16384 x 16384 pixels takes 1 GiB while it is drawn).
inline constexpr int kMaxPictureSide = 16384;
/// Narrowest picture, pixels.
inline constexpr int kMinPictureWidth = 64;
/// Largest text scale.
inline constexpr int kMaxTextScale = 8;
/// Font family of all text, through Cairo's font selection (fontconfig picks the nearest
/// installed font when this one is missing; Debian's fonts-dejavu-core has it).
inline constexpr const char* kPictureFontFamily = "DejaVu Sans";
/// Font size (the em) per unit of text_scale, pixels: the default text_scale 2 sets text at 14
/// pixels.
inline constexpr float kFontSizePerTextScale = 7.0f;
/// Largest auto-fit margin, as a fraction of the content's larger side.
inline constexpr float kMaxPictureMargin = 10.0f;
/// An auto-sized plot area is between these multiples of its width tall, whatever the
/// content's aspect ratio (a lone horizontal wall still gets a readable strip).
inline constexpr float kMinPlotAspect = 0.25f;
inline constexpr float kMaxPlotAspect = 1.5f;
/// Padding around the picture and between blocks, text_scale units.
inline constexpr int kPicturePadding = 4;
/// Horizontal gap between panels and between legend entries, text_scale units.
inline constexpr int kPanelGap = 8;
/// Extra space below the title line, text_scale units.
inline constexpr int kTitleGap = 2;
/// Size of a legend swatch, text_scale units.
inline constexpr int kSwatchWidth = 8;
inline constexpr int kSwatchHeight = 6;
/// Space between a legend swatch and its name, text_scale units.
inline constexpr int kSwatchTextGap = 3;
/// A label's text starts this many pixels right of its anchor point, with its baseline this
/// many pixels above it.
inline constexpr int kLabelOffset = 4;

/// A rectangle of whole pixels: columns [x, x + width), rows [y, y + height).
struct PixelBox {
  int x = 0, y = 0, width = 0, height = 0;
  friend constexpr bool operator==(PixelBox, PixelBox) noexcept = default;
};

/// How a picture is laid out. Checked by the Picture constructor.
struct PictureOptions {
  int width = 800;                ///< image width, pixels, [kMinPictureWidth, kMaxPictureSide]
  /// Height of the panels' plot areas, pixels, [0, kMaxPictureSide]; 0: from the content's
  /// aspect ratio (the tallest panel's), kept within [kMinPlotAspect, kMaxPlotAspect] of the
  /// panel width.
  int plot_height = 0;
  bool y_up = true;               ///< world y points up the image (false: down, as on screens)
  /// World rectangle shown by every panel without one of its own; empty: each panel fits its
  /// content. Must be finite with min < max on both axes.
  std::optional<Aabb> world;
  /// Auto-fit margin on every side, a fraction of the content's larger side, [0, kMaxPictureMargin].
  float margin = 0.08f;
  /// Size of all text (kFontSizePerTextScale pixels per unit) and of the spacing around it,
  /// [1, kMaxTextScale].
  int text_scale = 2;
  bool legend = true;             ///< list the roles drawn, with their swatches
  std::string title;              ///< top line (UTF-8); empty: none
};

/// One panel laid out: where its world rectangle lands in the image.
struct PanelView {
  std::string title;      ///< drawn above the plot area, fitted to its width
  Vec2 title_origin{0.0f, 0.0f};  ///< start of the title's baseline, pixels
  PixelBox plot;          ///< plot area, pixels; drawing is clipped to it
  Aabb world;             ///< world rectangle, centred in `plot`
  float scale = 1.0f;     ///< pixels per world unit: min(plot.width / world width, plot.height / world height)
  bool y_up = true;

  /// Image position of world point `p`: the plot centre plus `scale` times the offset of `p`
  /// from the world rectangle's centre (y negated when y_up).
  [[nodiscard]] Vec2 to_image(Vec2 p) const noexcept;
};

/// One legend entry laid out.
struct LegendEntry {
  DrawRole role = DrawRole::static_geometry;
  PixelBox swatch;                ///< the role's sample, pixels
  Vec2 text_origin{0.0f, 0.0f};   ///< start of the baseline of the role's name (to_string(role)), pixels
  float text_width = 0.0f;        ///< advance width of the name as Cairo measures it, pixels
};

/// Where everything goes, pixels.
struct PictureLayout {
  int width = 0;                    ///< image size, pixels
  int height = 0;
  float font_size = 0.0f;           ///< size (the em) of all text, pixels
  /// The title line (with a note of skipped calls), fitted to the width: cut where it would
  /// overflow, ending in an ellipsis.
  std::string title;
  Vec2 title_origin{0.0f, 0.0f};    ///< start of the title's baseline, pixels
  std::vector<PanelView> panels;    ///< at least one (an empty picture has one empty panel)
  std::vector<LegendEntry> legend;  ///< empty when the legend is off or nothing was drawn
};

/// An arrow in image pixels: a shaft and a filled triangular head.
struct ArrowPixels {
  Vec2 from;        ///< tail
  Vec2 shaft_end;   ///< where the shaft meets the head's base
  Vec2 tip;         ///< the `to` point
  Vec2 head_left;   ///< the head's base corners
  Vec2 head_right;
};

/// A renderer of a laid-out picture: receives everything in image pixels (x right, y down), in
/// drawing order. CairoSink (cairo_picture.hpp) implements it; a game could too (its own debug
/// overlay). Sizes of strokes and markers come from `draw_style(role)`. Text arrives as valid
/// UTF-8 without control characters (Picture replaces anything else by U+FFFD).
class PixelSink {
 public:
  virtual ~PixelSink() = default;
  /// Starts the image: size, background, the title line.
  virtual void begin(const PictureLayout& layout) = 0;
  /// Starts a panel (frame, title); later calls up to end_panel are clipped to `view.plot`.
  virtual void begin_panel(const PanelView& view) = 0;
  /// Ends the panel begun last: drawing reaches the whole image again.
  virtual void end_panel() = 0;
  /// Starts the legend: its swatches come as the calls below (unclipped), its names as text().
  virtual void begin_legend() = 0;
  /// Ends the legend.
  virtual void end_legend() = 0;
  /// A solid convex polygon (either winding), grown by `radius` pixels: 1 vertex is a disc, 2 a
  /// capsule.
  virtual void polygon(std::span<const Vec2> vertices, float radius, DrawRole role) = 0;
  /// A solid disc of `radius` pixels.
  virtual void circle(Vec2 center, float radius, DrawRole role) = 0;
  /// Every point within `radius` pixels of the segment a-b, solid.
  virtual void capsule(Vec2 a, Vec2 b, float radius, DrawRole role) = 0;
  /// A stroke from a to b.
  virtual void segment(Vec2 a, Vec2 b, DrawRole role) = 0;
  /// A stroked shaft and a filled head.
  virtual void arrow(const ArrowPixels& arrow, DrawRole role) = 0;
  /// The role's point marker centred on `p`.
  virtual void point(Vec2 p, DrawRole role) = 0;
  /// A caption whose baseline starts at `origin`, in the role's colour, on a thin halo of the
  /// background colour so it reads over shapes.
  virtual void label(Vec2 origin, std::string_view text, DrawRole role) = 0;
  /// Plain text (legend names) whose baseline starts at `origin`.
  virtual void text(Vec2 origin, std::string_view text) = 0;
  /// Ends the image.
  virtual void end() = 0;
};

/// Debug geometry recorded in panels (the DebugDraw calls, world space), with the options that
/// lay it out. Calls with a non-finite coordinate or radius, a negative radius, or a polygon of
/// no vertices are skipped and counted (`skipped()`, and a note in the title): a renderer fed by
/// a running game must not take it down over one bad body. Option errors throw. Text (title,
/// panel titles, labels) is UTF-8: ill-formed bytes and control characters become U+FFFD.
class Picture : public DebugDraw {
 public:
  /// Throws InvalidInput naming the option when one is out of its documented range.
  explicit Picture(PictureOptions options = {});

  /// Replaces the title line.
  void set_title(std::string title) { options_.title = std::move(title); }
  /// Starts a new panel, to the right of the previous ones, with its own title and world
  /// rectangle (given, which must be finite with min < max, else throws InvalidInput; or
  /// fitted to what is drawn in it). Calls before the first begin_panel go to an untitled panel.
  void begin_panel(std::string_view title, std::optional<Aabb> world = std::nullopt);

  void draw_polygon(std::span<const Vec2> vertices, float radius, DrawRole role) override;
  void draw_circle(Vec2 center, float radius, DrawRole role) override;
  void draw_capsule(Vec2 a, Vec2 b, float radius, DrawRole role) override;
  void draw_segment(Vec2 a, Vec2 b, DrawRole role) override;
  void draw_arrow(Vec2 from, Vec2 to, DrawRole role) override;
  void draw_point(Vec2 p, DrawRole role) override;
  void draw_label(Vec2 at, std::string_view text, DrawRole role) override;

  [[nodiscard]] const PictureOptions& options() const noexcept { return options_; }
  /// Number of panels so far.
  [[nodiscard]] int panel_count() const noexcept { return static_cast<int>(panels_.size()); }
  /// The roles of every recorded call (labels included), each once, in DrawRole order.
  [[nodiscard]] std::vector<DrawRole> roles_drawn() const;
  /// Number of calls skipped for bad input.
  [[nodiscard]] int skipped() const noexcept { return skipped_; }

  /// Lays the picture out: no drawing, but text is measured with Cairo. Throws std::bad_alloc
  /// when Cairo runs out of memory.
  [[nodiscard]] PictureLayout layout() const;
  /// Lays the picture out and sends it to `sink` in image pixels: the title, each panel and its
  /// calls in the order they were made, then the legend. Calls wholly outside their panel's
  /// plot area are culled; segments, arrows and rays are clipped to near it.
  void replay(PixelSink& sink) const;

 private:
  enum class Kind : unsigned char { polygon, circle, capsule, segment, arrow, point, label };
  struct Item {
    Kind kind;
    DrawRole role;
    std::uint32_t first;  ///< into points_
    std::uint32_t count;
    float radius;
    std::uint32_t text;   ///< into texts_ (labels)
  };
  struct Panel {
    std::string title;
    std::optional<Aabb> world;
    std::vector<Item> items;
    Aabb bounds;          ///< of the items' world points and radii
    bool empty = true;
  };

  Panel& current_panel();
  bool accept(std::span<const Vec2> points, float radius);
  void record(Kind kind, DrawRole role, std::span<const Vec2> points, float radius,
              std::string_view text = {});
  void replay_item(const Item& item, const PanelView& view, PixelSink& sink,
                   std::vector<Vec2>& mapped) const;

  PictureOptions options_;
  std::vector<Panel> panels_;
  std::vector<Vec2> points_;
  std::vector<std::string> texts_;
  std::uint32_t roles_mask_ = 0;
  int skipped_ = 0;
};

}  // namespace collide
