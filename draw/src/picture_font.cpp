#include "picture_font.hpp"

#include <collide/draw/picture.hpp>

#include <new>
#include <vector>

namespace collide {
namespace {

/// U+FFFD REPLACEMENT CHARACTER, in UTF-8.
constexpr std::string_view kReplacement = "\xef\xbf\xbd";
/// U+2026 HORIZONTAL ELLIPSIS, in UTF-8: the end of a cut title.
constexpr std::string_view kEllipsis = "\xe2\x80\xa6";
/// Largest Unicode code point.
constexpr char32_t kMaxCodePoint = 0x10ffff;

/// True for code points a picture shows as they are: not a control character (C0, DEL, C1) and
/// not a noncharacter (U+FDD0..U+FDEF and the last two of every plane, which Cairo refuses).
bool shown(char32_t cp) noexcept {
  const bool control = cp < 0x20 || (cp >= 0x7f && cp < 0xa0);
  const bool noncharacter = (cp >= 0xfdd0 && cp <= 0xfdef) || (cp & 0xfffe) == 0xfffe;
  return !control && !noncharacter;
}

/// Length of the UTF-8 sequence that starts with `lead`, the bits of the code point it carries,
/// and the smallest code point that needs this length (shorter forms are ill-formed); length 0
/// for a byte no sequence starts with.
struct Lead {
  int length;
  char32_t bits;
  char32_t min;
};
Lead decode_lead(unsigned char lead) noexcept {
  if (lead < 0x80) return {1, lead, 0};
  if ((lead & 0xe0) == 0xc0) return {2, static_cast<char32_t>(lead & 0x1f), 0x80};
  if ((lead & 0xf0) == 0xe0) return {3, static_cast<char32_t>(lead & 0x0f), 0x800};
  if ((lead & 0xf8) == 0xf0) return {4, static_cast<char32_t>(lead & 0x07), 0x10000};
  return {0, 0, 0};
}

bool is_continuation(char c) noexcept { return (static_cast<unsigned char>(c) & 0xc0) == 0x80; }

}  // namespace

void use_picture_font(cairo_t* cr, double size) noexcept {
  cairo_select_font_face(cr, kPictureFontFamily, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_font_options_t* options = cairo_font_options_create();
  cairo_font_options_set_hint_metrics(options, CAIRO_HINT_METRICS_OFF);
  cairo_font_options_set_antialias(options, CAIRO_ANTIALIAS_GRAY);  // no colour fringes in PNGs
  cairo_set_font_options(cr, options);
  cairo_font_options_destroy(options);
}

std::string clean_text(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const Lead lead = decode_lead(static_cast<unsigned char>(text[i]));
    const auto length = static_cast<std::size_t>(lead.length);
    bool ok = length > 0 && i + length <= text.size();
    char32_t cp = lead.bits;
    for (std::size_t k = 1; ok && k < length; ++k) {
      ok = is_continuation(text[i + k]);
      cp = cp << 6 | (static_cast<unsigned char>(text[i + k]) & 0x3f);
    }
    ok = ok && cp >= lead.min && cp <= kMaxCodePoint && !(cp >= 0xd800 && cp <= 0xdfff);
    if (ok && shown(cp)) {
      out.append(text.substr(i, length));
    } else {
      out += kReplacement;
    }
    i += ok ? length : 1;  // an ill-formed sequence: one replacement per byte
  }
  return out;
}

TextMeasurer::TextMeasurer(double size) {
  // The smallest surface: only its font machinery is used.
  surface_ = cairo_image_surface_create(CAIRO_FORMAT_A8, 1, 1);
  cr_ = cairo_create(surface_);
  use_picture_font(cr_, size);
  cairo_font_extents_t font;
  cairo_font_extents(cr_, &font);
  cairo_text_extents_t capital;
  cairo_text_extents(cr_, "H", &capital);
  // Any failure so far (the surface, the context, the font) leaves the context in an error
  // state; with valid arguments that can only be a lack of memory.
  if (cairo_status(cr_) != CAIRO_STATUS_SUCCESS) {
    cairo_destroy(cr_);
    cairo_surface_destroy(surface_);
    throw std::bad_alloc();
  }
  ascent_ = font.ascent;
  descent_ = font.descent;
  cap_height_ = -capital.y_bearing;
}

TextMeasurer::~TextMeasurer() {
  cairo_destroy(cr_);
  cairo_surface_destroy(surface_);
}

double TextMeasurer::width(std::string_view text) const {
  if (text.empty()) return 0.0;
  const std::string terminated(text);  // Cairo takes NUL-terminated strings
  cairo_text_extents_t extents;
  cairo_text_extents(cr_, terminated.c_str(), &extents);
  return extents.x_advance;
}

std::string TextMeasurer::fit(std::string_view text, double max_width) const {
  if (width(text) <= max_width) return std::string(text);
  // Byte offsets where a code point ends: candidate cuts, the longest first ruled out above.
  std::vector<std::size_t> cuts;
  for (std::size_t i = 1; i < text.size(); ++i) {
    if (!is_continuation(text[i])) cuts.push_back(i);
  }
  auto cut = [&](std::size_t end) { return std::string(text.substr(0, end)) + std::string(kEllipsis); };
  if (width(kEllipsis) > max_width) return {};
  // Binary search for the longest prefix that fits with its ellipsis (widths grow with it).
  std::size_t lo = 0, hi = cuts.size();  // cuts[0, lo) fit; cuts[hi, end) do not
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (width(cut(cuts[mid])) <= max_width) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  return lo == 0 ? std::string(kEllipsis) : cut(cuts[lo - 1]);
}

}  // namespace collide
