// The byte prescan and the SAX/DOM parse of a scene's text (server/codec/document.h).
#include "server/codec/document.h"

#include <algorithm>
#include <optional>
#include <utility>

namespace lambert::codec {
namespace {

constexpr int kMaxNestingDepth = 256;

// ---- 1. byte scan -----------------------------------------------------------------------------

// Length of the well-formed UTF-8 sequence starting at s (RFC 3629 table: no overlong forms, no
// surrogates, nothing above U+10FFFF), or 0 if it is not well formed.
std::size_t utf8_sequence_length(const unsigned char* s, std::size_t available) {
  const unsigned char c = s[0];
  std::size_t len = 0;
  unsigned char lo = 0x80, hi = 0xBF;  // allowed range of the second byte
  if (c >= 0xC2 && c <= 0xDF) len = 2;
  else if (c == 0xE0) len = 3, lo = 0xA0;
  else if ((c >= 0xE1 && c <= 0xEC) || c == 0xEE || c == 0xEF) len = 3;
  else if (c == 0xED) len = 3, hi = 0x9F;
  else if (c == 0xF0) len = 4, lo = 0x90;
  else if (c >= 0xF1 && c <= 0xF3) len = 4;
  else if (c == 0xF4) len = 4, hi = 0x8F;
  else return 0;
  if (available < len || s[1] < lo || s[1] > hi) return 0;
  for (std::size_t k = 2; k < len; ++k)
    if (s[k] < 0x80 || s[k] > 0xBF) return 0;
  return len;
}

// Rejects invalid UTF-8 anywhere and brackets nested deeper than kMaxNestingDepth (outside strings),
// in one linear pass with no recursion, before any parser or destructor sees the text.
std::optional<DecodeError> prescan(std::string_view text) {
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  int depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < n;) {
    const unsigned char c = s[i];
    if (c >= 0x80) {
      const std::size_t len = utf8_sequence_length(s + i, n - i);
      if (len == 0) return DecodeError{"", "invalid UTF-8 at byte offset " + std::to_string(i)};
      i += len;
      escaped = false;
      continue;
    }
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxNestingDepth)
        return DecodeError{"", "nesting deeper than " + std::to_string(kMaxNestingDepth) +
                                   " levels at byte offset " + std::to_string(i)};
    } else if (c == ']' || c == '}') {
      --depth;  // unbalanced input is the parser's to report, with its line and column
    }
    ++i;
  }
  return std::nullopt;
}

// ---- 2. parse -----------------------------------------------------------------------------------

// Builds the DOM like nlohmann's own DOM parser and additionally reports duplicate keys.
class DomBuilder final : public json::json_sax_t {
 public:
  explicit DomBuilder(json& root) : root_(root) {}

  std::vector<DecodeError> duplicate_keys;
  std::size_t omitted_duplicate_keys = 0;
  std::string parse_error_message;
  std::string parse_error_pointer;  // set when the error belongs to one value (number overflow)

  bool null() override { return add(json(nullptr)); }
  bool boolean(bool v) override { return add(json(v)); }
  bool number_integer(number_integer_t v) override { return add(json(v)); }
  bool number_unsigned(number_unsigned_t v) override { return add(json(v)); }
  bool number_float(number_float_t v, const string_t&) override { return add(json(v)); }
  bool string(string_t& v) override { return add(json(std::move(v))); }
  bool binary(binary_t&) override { return false; }  // never produced by JSON text

  bool start_object(std::size_t) override {
    frames_.push_back({add_value(json::object()), true, {}});
    return true;
  }
  bool key(string_t& k) override {
    Frame& f = frames_.back();
    if (f.value->contains(k)) {
      if (duplicate_keys.size() < kMaxListedErrors)
        duplicate_keys.push_back(bounded_error(key_ptr(path(), k), "duplicate key " + quote_text(k) +
                                                                       " (JSON keeps only one of them)"));
      else
        ++omitted_duplicate_keys;
    }
    slot_ = &(*f.value)[k];
    f.key = std::move(k);
    return true;
  }
  bool end_object() override { frames_.pop_back(); return true; }
  bool start_array(std::size_t) override {
    frames_.push_back({add_value(json::array()), false, {}});
    return true;
  }
  bool end_array() override { frames_.pop_back(); return true; }
  bool parse_error(std::size_t, const std::string&, const json::exception& ex) override {
    parse_error_message = ex.what();
    // out_of_range.406: a number like 1e400 that does not fit a double. The text is otherwise
    // well formed, so the value's pointer is known: the next member or element being parsed.
    if (ex.id == 406 && !frames_.empty()) {
      const Frame& f = frames_.back();
      parse_error_pointer = f.is_object ? key_ptr(path(), f.key) : index_ptr(path(), f.value->size());
    }
    return false;
  }

 private:
  struct Frame {
    json* value;       // an object or array still being filled (pointers stay valid: siblings are
    bool is_object;    // only appended after this container is closed)
    std::string key;   // object: the key of the member being parsed
  };

  bool add(json&& v) { add_value(std::move(v)); return true; }
  json* add_value(json&& v) {
    if (frames_.empty()) {
      root_ = std::move(v);
      return &root_;
    }
    Frame& f = frames_.back();
    if (f.is_object) {
      *slot_ = std::move(v);
      return slot_;
    }
    f.value->push_back(std::move(v));
    return &f.value->back();
  }
  // Pointer of the innermost open container. Keys may be long and 256 levels deep: a pointer longer
  // than kMaxErrorTextBytes is built from its two ends only, as a report shortens it (bounded_error).
  std::string path() const {
    const std::size_t levels = frames_.empty() ? 0 : frames_.size() - 1;
    std::size_t total = 0;
    for (std::size_t i = 0; i < levels; ++i) total += segment_bytes(i);
    std::string head, tail;
    std::size_t first = 0, last = levels;
    if (total <= kMaxErrorTextBytes) {
      while (first < levels) head += segment(first++);
      return head;
    }
    const std::size_t keep = (kMaxErrorTextBytes - kElisionMarkBytes) / 2;
    while (first < last && head.size() < keep) head += segment(first++);
    while (last > first && tail.size() < keep) tail = segment(--last) + tail;
    const std::string_view h = utf8_prefix(head, keep), t = utf8_suffix(tail, keep);
    return elided(h, total - h.size() - t.size(), t);
  }
  std::size_t segment_bytes(std::size_t i) const {
    const Frame& f = frames_[i];
    if (!f.is_object) return 1 + std::to_string(f.value->size() - 1).size();
    return 1 + f.key.size() + static_cast<std::size_t>(std::count_if(f.key.begin(), f.key.end(), [](char c) {
             return c == '~' || c == '/';
           }));
  }
  // "/key" (escaped) or "/index" of the member being filled at level i.
  std::string segment(std::size_t i) const {
    const Frame& f = frames_[i];
    return f.is_object ? key_ptr("", f.key) : index_ptr("", f.value->size() - 1);
  }

  json& root_;
  std::vector<Frame> frames_;
  json* slot_ = nullptr;
};

}  // namespace

ParsedDocument parse_document(const std::string& text) {
  ParsedDocument parsed;
  if (auto e = prescan(text)) {
    parsed.fatal.push_back(std::move(*e));
    return parsed;
  }
  DomBuilder builder(parsed.doc);
  const bool ok = json::sax_parse(text, &builder, json::input_format_t::json,
                                  /*strict=*/true, /*ignore_comments=*/false);
  if (!ok) {
    // "[json.exception.parse_error.101] parse error at line 2, column 12: ..." -> without the tag.
    std::string message = builder.parse_error_message;
    const auto tag_end = message.find("] ");
    if (message.rfind("[json.exception", 0) == 0 && tag_end != std::string::npos)
      message.erase(0, tag_end + 2);
    // The parser quotes the token it last read, which may be a megabyte-long string.
    if (!builder.parse_error_pointer.empty())
      parsed.fatal.push_back(bounded_error(builder.parse_error_pointer, message + " (not a finite double)"));
    else
      parsed.fatal.push_back(bounded_error("", "invalid JSON: " + message));
    return parsed;
  }
  parsed.duplicate_keys = std::move(builder.duplicate_keys);
  parsed.omitted_duplicate_keys = builder.omitted_duplicate_keys;
  return parsed;
}

}  // namespace lambert::codec
