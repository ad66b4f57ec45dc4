// The bitmap font: every printable glyph is its own pattern inside the 5 x 7 box, text counts
// UTF-8 code points, and drawn text stays inside its documented box.
#include <collide/draw/bitmap_font.hpp>

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

namespace collide {
namespace {

std::string rows_of(char32_t c) {
  const std::uint8_t* r = glyph_rows(c);
  return {r, r + kGlyphHeight};
}

TEST(BitmapFont, PrintableGlyphsAreDistinctAndFitTheBox) {
  std::set<std::string> seen;
  for (char32_t c = 0x20; c <= 0x7e; ++c) {
    const auto rows = rows_of(c);
    int ink = 0;
    for (const char ch : rows) {
      const auto r = static_cast<std::uint8_t>(ch);
      EXPECT_EQ(r >> kGlyphWidth, 0) << "glyph " << static_cast<int>(c) << " wider than the box";
      ink += __builtin_popcount(r);
    }
    if (c == ' ') {
      EXPECT_EQ(ink, 0);
    } else {
      EXPECT_GT(ink, 0) << static_cast<char>(c);
    }
    EXPECT_TRUE(seen.insert(rows).second) << "glyph '" << static_cast<char>(c) << "' repeats another";
  }
  EXPECT_EQ(rows_of(U'é'), rows_of(0x01));  // no glyph: the box
  EXPECT_FALSE(seen.count(rows_of(U'é')));
}

TEST(BitmapFont, WidthsCountCodePoints) {
  EXPECT_EQ(text_columns(""), 0);
  EXPECT_EQ(text_columns("abc"), 3);
  EXPECT_EQ(text_columns("h\xc3\xa9llo"), 5);             // é is 2 bytes, 1 column
  EXPECT_EQ(text_columns("\xe2\x9c\x93!"), 2);            // ✓ is 3 bytes
  EXPECT_EQ(text_columns("\xff" "a"), 2);                 // a stray byte is one column
  EXPECT_EQ(text_columns("\xe2\x9c"), 2);                 // a cut sequence: one column per byte
  EXPECT_EQ(text_columns("\xc0\xaf"), 2);                 // overlong '/': ill-formed
  EXPECT_EQ(text_columns("\xed\xa0\x80"), 3);             // a surrogate: ill-formed
  EXPECT_EQ(text_columns("\xf0\x9f\x99\x82"), 1);         // U+1F642, 4 bytes
  std::size_t i = 0;
  EXPECT_EQ(next_code_point("\xe2\x9c\x93", i), U'\u2713');
  EXPECT_EQ(i, 3u);
  i = 0;
  EXPECT_EQ(next_code_point("\xe2\x9c" "a", i), kReplacementCharacter);
  EXPECT_EQ(i, 1u);
  EXPECT_EQ(text_width("", 3), 0);
  EXPECT_EQ(text_width("ab", 1), 2 * kGlyphAdvance - 1);
  EXPECT_EQ(text_width("ab", 3), 3 * (2 * kGlyphAdvance - 1));
}

TEST(BitmapFont, TextPaintsInsideItsBoxOnly) {
  const Color white{255, 255, 255, 255}, ink{10, 20, 30, 255};
  const std::string text = "Hi! g_y|@ \xc3\xa9";
  for (const int scale : {1, 2, 3}) {
    Canvas c(240, 60, white);
    const int x = 7, y = 11;
    draw_text(c, x, y, text, ink, scale);
    const int w = text_width(text, scale), h = kGlyphHeight * scale;
    int inked = 0;
    for (int j = 0; j < c.height(); ++j) {
      for (int i = 0; i < c.width(); ++i) {
        const bool in_box = i >= x && i < x + w && j >= y && j < y + h;
        if (c.pixel(i, j) == ink) {
          EXPECT_TRUE(in_box) << i << ", " << j << " scale " << scale;
          ++inked;
        } else {
          EXPECT_EQ(c.pixel(i, j), white);
        }
      }
    }
    // Ink is whole glyph pixels: a multiple of scale^2, and the left and right columns are used.
    EXPECT_EQ(inked % (scale * scale), 0);
    EXPECT_GT(inked, 40 * scale * scale);
    int left = 0, right = 0;
    for (int j = y; j < y + h; ++j) {
      left += c.pixel(x, j) == ink;
      right += c.pixel(x + w - 1, j) == ink;
    }
    EXPECT_GT(left, 0);
    EXPECT_GT(right, 0);
  }
}

TEST(BitmapFont, TextIsClippedAndZeroScaleDrawsNothing) {
  Canvas c(20, 20);
  draw_text(c, -1, -1, "WWWWWWWWWW", {0, 0, 0, 255}, 2);     // partly off the canvas
  draw_text(c, 2147483000, 5, "W", {0, 0, 0, 255}, 8);        // far off: no overflow
  draw_text(c, 0, 0, "W", {255, 0, 0, 255}, 0);
  EXPECT_EQ(c.pixel(0, 0), (Color{0, 0, 0, 255}));           // 'W' has ink in its top-left
  for (int j = 0; j < 20; ++j) {
    for (int i = 0; i < 20; ++i) EXPECT_NE(c.pixel(i, j), (Color{255, 0, 0, 255}));
  }
}

}  // namespace
}  // namespace collide
