// Naming the place of a JSON syntax error: a SAX pass that only follows where it is.

#include "json_syntax.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace collide::io {
namespace {

using Json = nlohmann::json;

/// A SAX pass that only follows where it is in the document, so a syntax error can name the
/// element being read: "layers[0].objects[3] (id=12).polygon[2]".
class PathTracker {
 public:
  bool null() { return value(); }
  bool boolean(bool) { return value(); }
  bool number_integer(Json::number_integer_t v) { return id(static_cast<long long>(v)); }
  bool number_unsigned(Json::number_unsigned_t v) { return id(static_cast<long long>(v)); }
  bool number_float(Json::number_float_t, const Json::string_t&) { return value(); }
  bool string(Json::string_t&) { return value(); }
  bool binary(Json::binary_t&) { return value(); }
  bool start_object(std::size_t) { return push(false); }
  bool start_array(std::size_t) { return push(true); }
  bool end_object() { return pop(); }
  bool end_array() { return pop(); }
  bool key(Json::string_t& k) {
    frames_.back().key = k;
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) { return false; }

  /// The element the parser was in: "root" at the top.
  [[nodiscard]] std::string path() const {
    std::string out;
    for (std::size_t i = 0; i < frames_.size(); ++i) {
      const Frame& f = frames_[i];
      if (i == kMaxShownPathSteps) {
        out.append("...");
        break;
      }
      if (i > 0 && f.has_id) out.append(" (id=").append(std::to_string(f.id)).append(")");
      if (f.array) {
        out.append("[").append(std::to_string(f.index)).append("]");
      } else if (!f.key.empty()) {
        if (!out.empty()) out += '.';
        append_path_key(out, f.key);
      }
    }
    return out.empty() ? "root" : out;
  }

 private:
  struct Frame {
    bool array = false;
    std::size_t index = 0;  ///< arrays: the element being read
    std::string key;        ///< objects: the member being read
    bool has_id = false;    ///< objects: an "id" member was read
    long long id = 0;
  };
  bool value() {  // a value finished in the current container
    if (frames_.empty()) return true;
    Frame& f = frames_.back();
    if (f.array) {
      ++f.index;
    } else {
      f.key.clear();  // between members the error is in the object itself
    }
    return true;
  }
  bool id(long long v) {
    if (!frames_.empty() && !frames_.back().array && frames_.back().key == "id") {
      frames_.back().has_id = true;
      frames_.back().id = v;
    }
    return value();
  }
  bool push(bool array) {
    frames_.push_back({array, 0, {}, false, 0});
    return true;
  }
  bool pop() {
    frames_.pop_back();
    return value();
  }
  std::vector<Frame> frames_;
};

}  // namespace

void append_path_key(std::string& path, std::string_view key) {
  for (const char c : key) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      constexpr char kHex[] = "0123456789abcdef";
      path.append("\\u00").append(1, kHex[u >> 4]).append(1, kHex[u & 15]);
    } else {
      path += c;
    }
  }
}

std::string json_path_at_syntax_error(std::string_view text) {
  PathTracker tracker;
  (void)Json::sax_parse(text.begin(), text.end(), &tracker);
  return tracker.path();
}

std::size_t json_too_deep_at(std::string_view text, std::size_t max_depth) {
  std::size_t depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) return i;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::string_view::npos;
}

}  // namespace collide::io
