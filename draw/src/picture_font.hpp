#pragma once
// The font of every picture, shared by the layout (which measures text) and the renderer (which
// draws it), so that text drawn is exactly as wide as the layout measured it. Measurements are
// doubles, as Cairo gives them; the layout keeps floats.

#include <cairo.h>

#include <string>
#include <string_view>

namespace collide {

/// Selects kPictureFontFamily at `size` pixels on `cr`, with font options that keep text
/// metrics the same on every surface: metric hinting off (an image surface would otherwise round
/// advances to whole pixels, and text would be wider in a PNG than in an SVG or PDF).
void use_picture_font(cairo_t* cr, double size) noexcept;

/// `text` as valid UTF-8 that Cairo accepts: every ill-formed byte (a cut or corrupt sequence,
/// an overlong form, a surrogate, a code point past U+10FFFF), every control character and every
/// Unicode noncharacter becomes U+FFFD.
[[nodiscard]] std::string clean_text(std::string_view text);

/// Text measured in the pictures' font, on a scratch context of its own.
class TextMeasurer {
 public:
  /// Measures at `size` pixels. Throws std::bad_alloc when Cairo cannot make the context.
  explicit TextMeasurer(double size);
  ~TextMeasurer();
  TextMeasurer(const TextMeasurer&) = delete;
  TextMeasurer& operator=(const TextMeasurer&) = delete;

  /// Advance width of `text` (valid UTF-8: clean_text), pixels.
  [[nodiscard]] double width(std::string_view text) const;
  /// `text` cut to at most `max_width` pixels: itself when it fits, else its longest prefix of
  /// whole code points followed by an ellipsis that fits, else empty.
  [[nodiscard]] std::string fit(std::string_view text, double max_width) const;
  /// The font's ascent (baseline to the top of the tallest glyphs) and descent (baseline to the
  /// bottom of descenders), pixels.
  [[nodiscard]] double ascent() const noexcept { return ascent_; }
  [[nodiscard]] double descent() const noexcept { return descent_; }
  /// Height of capital letters above the baseline, pixels.
  [[nodiscard]] double cap_height() const noexcept { return cap_height_; }

 private:
  cairo_surface_t* surface_ = nullptr;
  cairo_t* cr_ = nullptr;
  double ascent_ = 0.0;
  double descent_ = 0.0;
  double cap_height_ = 0.0;
};

}  // namespace collide
