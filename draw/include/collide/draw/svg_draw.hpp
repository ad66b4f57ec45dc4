#pragma once
/// @file
/// Debug pictures as standalone SVG documents: a Picture (panels, palette, legend, title; see
/// picture.hpp) written as SVG 1.1 text in image pixels, so every stroke width and marker size
/// is the palette's, whatever the world scale.
///
/// The document: a white background rect; the title as `<text class="title">`; per panel a
/// `<rect class="frame">`, a `<text class="panel-title">` and a `<g class="panel">` clipped to the
/// plot area, holding one element per recorded call in call order, each with the class
/// `role-NAME` where NAME is `to_string(role)` in lower case with spaces as '-' (e.g.
/// `role-fast-body`): polygon -> `<polygon>` (rounded: `<path>` of lines and arcs), circle ->
/// `<circle>`, capsule -> `<path>`, segment -> `<line>`, arrow -> `<path>` (shaft and filled head),
/// point -> `<circle>` (dot) or `<path>` (cross), label -> `<text>`; then `<g class="legend">` with
/// one swatch element and one `<text class="legend-text">` per role drawn. Coordinates are
/// printed with at most 2 decimals; text is XML-escaped (invalid UTF-8 and control characters
/// become U+FFFD).

#include <collide/draw/picture.hpp>

#include <filesystem>
#include <string>

namespace collide {

/// `picture` as an SVG document.
[[nodiscard]] std::string render_svg(const Picture& picture);

/// Writes `render_svg(picture)` to `path`. Throws InvalidInput naming the path when it cannot
/// be written.
void save_svg(const Picture& picture, const std::filesystem::path& path);

/// A DebugDraw that records a picture and writes it as SVG.
class SvgDraw final : public Picture {
 public:
  /// Throws InvalidInput when an option is out of range (see PictureOptions).
  explicit SvgDraw(PictureOptions options = {}) : Picture(std::move(options)) {}
  /// The SVG document of everything drawn so far.
  [[nodiscard]] std::string svg() const { return render_svg(*this); }
  /// Writes svg() to `path`; throws InvalidInput naming the path when it cannot be written.
  void save(const std::filesystem::path& path) const { save_svg(*this, path); }
};

}  // namespace collide
