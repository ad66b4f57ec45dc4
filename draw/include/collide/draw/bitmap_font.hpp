#pragma once
/// @file
/// A tiny built-in bitmap font for text on a Canvas (legends, titles, labels): 5 x 7 pixel
/// glyphs for printable ASCII (plus 2 rows of descenders for g, j, p, q, y), drawn as blocks of
/// `scale` x `scale` pixels. Every other code
/// point (a UTF-8 sequence counts as one) is drawn as a hollow box, so a text's width in
/// columns is the same as in the SVG renderer's monospace text.

#include <collide/draw/canvas.hpp>

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace collide {

/// Glyph width, font pixels.
inline constexpr int kGlyphWidth = 5;
/// Rows from the top of a glyph to its baseline (capital letters and digits fill them), font pixels.
inline constexpr int kGlyphAscent = 7;
/// Rows of a glyph including the descenders below the baseline, font pixels.
inline constexpr int kGlyphHeight = 9;
/// Horizontal distance from one glyph to the next (one blank column), font pixels.
inline constexpr int kGlyphAdvance = 6;
/// Distance from one text line to the next, font pixels.
inline constexpr int kLineAdvance = 11;

/// Rows of the glyph for `code_point`, top row first; bit 4 is the leftmost column. Printable
/// ASCII (0x20..0x7e) has its own glyph, everything else the hollow box.
[[nodiscard]] const std::uint8_t* glyph_rows(char32_t code_point) noexcept;

/// What an ill-formed UTF-8 byte decodes to (U+FFFD).
inline constexpr char32_t kReplacementCharacter = 0xfffd;

/// Decodes the UTF-8 sequence at `text[i]` (i < text.size()) and advances `i` past it. A
/// well-formed sequence (shortest form, no surrogates, at most U+10FFFF) gives its code point;
/// any other byte gives kReplacementCharacter and advances by that one byte, so a cut or
/// corrupt sequence shows one box per byte. The SVG renderer decodes with this too, so text
/// has the same number of columns in both renderers.
[[nodiscard]] char32_t next_code_point(std::string_view text, std::size_t& i) noexcept;

/// Number of characters (UTF-8 code points; each byte of an ill-formed sequence counts as one)
/// in `text`.
[[nodiscard]] int text_columns(std::string_view text) noexcept;

/// Width of `text` drawn at `scale`, pixels: columns * advance minus the trailing blank column
/// (0 for empty text).
[[nodiscard]] int text_width(std::string_view text, int scale) noexcept;

/// Draws `text` (UTF-8, one line: control characters show as boxes) with the top-left corner
/// of its first glyph at pixel (x, y). Pixels painted lie in [x, x + text_width) x
/// [y, y + kGlyphHeight * scale), clipped to the canvas. `scale` < 1 draws nothing.
void draw_text(Canvas& canvas, int x, int y, std::string_view text, Color color, int scale) noexcept;

}  // namespace collide
