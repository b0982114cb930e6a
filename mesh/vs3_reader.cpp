// The .vs3 reader (vs3_reader.h): lines are split into words at blanks, tabs and commas (View3D's
// separators); a word starting with ! or / ends the line's data (a comment). Each record is read from
// its own line, as View3D reads it (it skips whatever follows a record on its line: here that must be
// a comment); the numbers of an F 3a surface follow on the next lines.
#include "mesh/vs3_reader.h"

#include <algorithm>
#include <limits>
#include <cmath>
#include <cstdio>
#include <optional>
#include <span>

#include "mesh/mesh_text.h"
#include "mesh/vs3_parse.h"

namespace lambert::vs3 {

// ---- messages ---------------------------------------------------------------------------------

std::string Messages::where(int line) const { return name_ + ":" + std::to_string(line) + ": "; }

void Messages::error(int line, const std::string& message) {
  if (errors_.size() < kMaxErrors) errors_.push_back(where(line) + message);
  else ++dropped_;
}

void Messages::warn(int line, const std::string& message, std::vector<std::string>& into) const {
  into.push_back(where(line) + message);
}

std::vector<std::string> Messages::take() {
  if (dropped_ > 0) errors_.push_back(name_ + ": " + std::to_string(dropped_) + " more errors not shown");
  return std::move(errors_);
}

namespace {

// ---- words ------------------------------------------------------------------------------------

struct Line {
  int number = 0;
  std::string_view text;               // without the line break
  std::vector<std::string_view> words;  // up to the first comment word
};

bool is_separator(char c) { return c == ' ' || c == '\t' || c == ',' || c == '\r'; }

std::vector<std::string_view> split_words(std::string_view text) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && is_separator(text[i])) ++i;
    if (i == text.size()) break;
    const std::size_t start = i;
    while (i < text.size() && !is_separator(text[i])) ++i;
    const std::string_view word = text.substr(start, i - start);
    if (word.front() == '!' || word.front() == '/') break;  // a comment to the end of the line
    words.push_back(word);
  }
  return words;
}

// What follows the first word of a line, blanks trimmed (a title, the control line).
std::string_view rest_of_line(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size() && is_separator(text[i])) ++i;
  while (i < text.size() && !is_separator(text[i])) ++i;
  while (i < text.size() && is_separator(text[i])) ++i;
  std::size_t end = text.size();
  while (end > i && is_separator(text[end - 1])) --end;
  return text.substr(i, end - i);
}

using mesh_io::in_quotes;

// A finite number, the whole word (mesh_io::parse_real: "+1.", ".5", "1.e-4"; not "nan" or "inf").
std::optional<double> to_number(std::string_view word) {
  const mesh_io::Real r = mesh_io::parse_real(word);
  return r.status == mesh_io::NumberStatus::Ok ? std::optional<double>(r.value) : std::nullopt;
}

std::optional<long long> to_whole(std::string_view word) {
  return mesh_io::parse_integer(word, std::numeric_limits<long long>::min(), std::numeric_limits<long long>::max());
}

// Whether `s` is valid UTF-8 (shortest forms, no surrogates) without control characters: names reach
// JSON and IDF files.
bool is_clean_utf8(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x80) {
      if (c < 0x20 || c == 0x7f) return false;
      ++i;
      continue;
    }
    std::size_t extra = 0;
    unsigned char lo = 0x80, hi = 0xbf;  // the range of the second byte
    if (c >= 0xc2 && c <= 0xdf) extra = 1;
    else if (c >= 0xe0 && c <= 0xef) extra = 2, lo = c == 0xe0 ? 0xa0 : 0x80, hi = c == 0xed ? 0x9f : 0xbf;
    else if (c >= 0xf0 && c <= 0xf4) extra = 3, lo = c == 0xf0 ? 0x90 : 0x80, hi = c == 0xf4 ? 0x8f : 0xbf;
    else return false;
    if (extra >= s.size() - i) return false;
    for (std::size_t k = 1; k <= extra; ++k) {
      const auto b = static_cast<unsigned char>(s[i + k]);
      if (k == 1 ? (b < lo || b > hi) : (b & 0xc0) != 0x80) return false;
    }
    i += 1 + extra;
  }
  return true;
}

// ---- the reader -------------------------------------------------------------------------------

// An F 3a surface waiting for its numbers: origin x y z, azimuth, tilt, then the shape's values.
struct PendingBlast {
  std::size_t surface = 0;  // index into Input::surfaces
  char shape = 'R';
  std::vector<double> numbers;
  std::size_t needed = 0;
};

class Reader {
 public:
  explicit Reader(std::string_view name) : messages_(name) {}
  ReadResult run(std::string_view text);

 private:
  // Returns false at the end of data.
  bool record(const Line& line);
  void title(const Line& line) { input_.title = std::string(rest_of_line(line.text)); }
  void controls(const Line& line);
  bool control_value(const Line& line, std::string_view key, std::string_view value);
  void format(const Line& line);
  void vertex(const Line& line);
  void surface(const Line& line, SurfaceKind kind);
  void common_fields(const Line& line, std::span<const std::string_view> fields, Surface& s);
  bool blast_numbers(const Line& line);
  void place_blast(const PendingBlast& pending, int line);
  void finish_controls();
  bool whole(const Line& line, std::string_view word, const char* what, long long lo, long long hi, int& into);

  Messages messages_;
  Input input_;
  std::optional<Geometry> geometry_;
  int format_line_ = 0, radiating_ = 0, control_line_ = 0;
  std::optional<PendingBlast> pending_;
};

bool Reader::whole(const Line& line, std::string_view word, const char* what, long long lo, long long hi,
                   int& into) {
  const auto v = to_whole(word);
  if (!v) {
    messages_.error(line.number, std::string(what) + ": expected a whole number, got " + in_quotes(word));
    return false;
  }
  if (*v < lo || *v > hi) {
    messages_.error(line.number, std::string(what) + " " + std::to_string(*v) + " is outside [" +
                                     std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return false;
  }
  into = static_cast<int>(*v);
  return true;
}

ReadResult Reader::run(std::string_view text) {
  if (text.size() > kMaxBytes) {
    messages_.error(0, "the file has " + std::to_string(text.size()) + " bytes; at most " +
                           std::to_string(kMaxBytes) + " are read");
    return {std::nullopt, messages_.take()};
  }
  int number = 0;
  for (std::size_t start = 0; start <= text.size();) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    Line line;
    line.number = ++number;
    line.text = text.substr(start, end - start);
    start = end + 1;
    if (line.text.size() > kMaxLineBytes) {
      messages_.error(line.number, "the line has " + std::to_string(line.text.size()) + " bytes; at most " +
                                       std::to_string(kMaxLineBytes));
      continue;
    }
    if (line.text.find('\0') != std::string_view::npos) {
      messages_.error(line.number, "the line holds a NUL byte (a .vs3 file is text)");
      continue;
    }
    line.words = split_words(line.text);
    if (line.words.empty()) continue;
    if (pending_) {
      if (blast_numbers(line)) continue;
    }
    if (!record(line)) break;
  }
  if (pending_) {
    messages_.error(input_.surfaces[pending_->surface].line,
                    "surface " + std::to_string(input_.surfaces[pending_->surface].number) + " needs " +
                        std::to_string(pending_->needed) + " numbers after it (origin x y z, azimuth, tilt, "
                        "then its shape's), the file gives " + std::to_string(pending_->numbers.size()));
  }
  if (!geometry_ && !messages_.any()) messages_.error(0, "no F line (the geometry: F 3 or F 3a)");
  finish_controls();
  if (!messages_.any()) check_surfaces(input_, messages_);
  if (messages_.any()) return {std::nullopt, messages_.take()};
  input_.geometry = *geometry_;
  return {std::move(input_), {}};
}

bool Reader::record(const Line& line) {
  const std::string_view id = line.words.front();
  const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(id.front())));
  if (c == 'E' || c == '*') return false;  // the end of data: nothing after it is read
  if (id.size() != 1) {
    messages_.error(line.number, "unknown line type " + in_quotes(id) +
                                     " (a line starts with one of T, C, F, V, S, M, N, O, E, * or a comment)");
    return true;
  }
  switch (c) {
    case 'T': title(line); break;
    case 'C': controls(line); break;
    case 'F': format(line); break;
    case 'V': vertex(line); break;
    case 'S': surface(line, SurfaceKind::Radiating); break;
    case 'M': surface(line, SurfaceKind::Mask); break;
    case 'N': surface(line, SurfaceKind::Null); break;
    case 'O': surface(line, SurfaceKind::Obstruction); break;
    case 'X':
      messages_.warn(line.number, "a coordinate transformation (X) is ignored, as View3D ignores it in 3-D files",
                     input_.warnings);
      break;
    default:
      messages_.error(line.number, "unknown line type " + in_quotes(id) +
                                       " (a line starts with one of T, C, F, V, S, M, N, O, E, * or a comment)");
  }
  return true;
}

void Reader::format(const Line& line) {
  if (line.words.size() != 2) {
    messages_.error(line.number, "expected 'F 3' or 'F 3a'");
    return;
  }
  std::optional<Geometry> g;
  const std::string_view f = line.words[1];
  if (f == "3") g = Geometry::Vertices;
  else if (f == "3a" || f == "3A") g = Geometry::Blast;
  if (!g) {
    messages_.error(line.number, "geometry " + in_quotes(f) + " is not read here: " +
                                     (f == "2" ? "F 2 is View3D's 2-D geometry; " : "") + "expected 3 or 3a");
    return;
  }
  if (geometry_ && *geometry_ != *g) {
    messages_.error(line.number, "a second F line with another geometry (the first is on line " +
                                     std::to_string(format_line_) + ")");
    return;
  }
  if (!geometry_ && (!input_.vertices.empty() || !input_.surfaces.empty())) {
    messages_.error(line.number, "the F line must come before the vertices and surfaces");
    return;
  }
  geometry_ = g;
  format_line_ = line.number;
}

void Reader::vertex(const Line& line) {
  if (geometry_ != Geometry::Vertices) {
    messages_.error(line.number, geometry_ ? "vertices (V) belong to F 3 files; this one is F 3a"
                                           : "a vertex before the F 3 line");
    return;
  }
  if (line.words.size() != 5) {
    messages_.error(line.number, "expected 'V n x y z' (" + std::to_string(line.words.size()) +
                                     " words, of which the data must be 5)");
    return;
  }
  const auto n = to_whole(line.words[1]);
  const long long expected = static_cast<long long>(input_.vertices.size()) + 1;
  if (!n || *n != expected) {
    messages_.error(line.number, "vertex " + in_quotes(line.words[1]) + " out of sequence: expected " +
                                     std::to_string(expected));
    return;
  }
  double xyz[3];
  for (int k = 0; k < 3; ++k) {
    const auto v = to_number(line.words[2 + k]);
    if (!v) {
      messages_.error(line.number, std::string("vertex ") + std::to_string(*n) + ": " + "xyz"[k] +
                                       " is not a finite number: " + in_quotes(line.words[2 + k]));
      return;
    }
    if (std::abs(*v) > 1e9) {
      messages_.error(line.number, "vertex " + std::to_string(*n) + ": |" + "xyz"[k] + "| exceeds 1e9");
      return;
    }
    xyz[k] = *v;
  }
  input_.vertices.push_back({xyz[0], xyz[1], xyz[2]});
}

// ---- the control line -------------------------------------------------------------------------

bool same_word(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

void Reader::controls(const Line& line) {
  control_line_ = line.number;
  std::string_view text = rest_of_line(line.text);
  if (const std::size_t bang = text.find('!'); bang != std::string_view::npos) text = text.substr(0, bang);
  // View3D splits the line at blanks, commas and '=' (strtok "= ,"): "encl=1", "encl = 1", "encl,1".
  std::vector<std::string_view> words;
  for (std::size_t i = 0; i < text.size();) {
    auto split = [](char c) { return is_separator(c) || c == '='; };
    while (i < text.size() && split(text[i])) ++i;
    const std::size_t start = i;
    while (i < text.size() && !split(text[i])) ++i;
    if (i > start) words.push_back(text.substr(start, i - start));
  }
  for (std::size_t k = 0; k < words.size(); k += 2) {
    if (k + 1 == words.size()) {
      messages_.error(line.number, "control " + in_quotes(words[k]) + " has no value");
      return;
    }
    control_value(line, words[k], words[k + 1]);
  }
}

bool Reader::control_value(const Line& line, std::string_view key, std::string_view value) {
  Controls& c = input_.controls;
  const std::string what = "control " + std::string(key.substr(0, 40));
  int flag = 0;
  if (same_word(key, "eps")) {
    const auto v = to_number(value);
    if (!v || !(*v > 0) || *v >= 1) {
      messages_.error(line.number, what + ": expected a number in (0, 1), got " + in_quotes(value));
      return false;
    }
    c.eps = *v;
    return true;
  }
  if (same_word(key, "maxU")) return whole(line, value, what.c_str(), 0, 1000, c.max_u);
  if (same_word(key, "maxO")) return whole(line, value, what.c_str(), 0, 1000, c.max_o);
  if (same_word(key, "minO")) return whole(line, value, what.c_str(), 0, 1000, c.min_o);
  if (same_word(key, "row")) return whole(line, value, what.c_str(), 0, 1 << 30, c.row);
  if (same_word(key, "col")) return whole(line, value, what.c_str(), 0, 1 << 30, c.col);
  if (same_word(key, "out")) return whole(line, value, what.c_str(), 0, 2, c.out);
  if (same_word(key, "list")) return whole(line, value, what.c_str(), 0, 1000, c.list);
  if (same_word(key, "maxV")) return whole(line, value, what.c_str(), 0, 1 << 30, c.max_v);
  for (auto [word, into] : {std::pair<const char*, bool*>{"encl", &c.enclosure}, {"emit", &c.emittances},
                            {"prjD", &c.prj_reverse}})
    if (same_word(key, word)) {
      if (!whole(line, value, what.c_str(), 0, 1, flag)) return false;
      *into = flag == 1;
      return true;
    }
  messages_.error(line.number, "unknown control " + in_quotes(key) +
                                   " (View3D's are eps, maxU, maxO, minO, row, col, encl, emit, out, list, "
                                   "prjD, maxV)");
  return false;
}

void Reader::finish_controls() {
  const Controls& c = input_.controls;
  if (c.col > 0 && c.row == 0) messages_.error(control_line_, "control col needs row (View3D's rule)");
  if (c.row > radiating_ || c.col > radiating_)
    messages_.error(control_line_, "control row or col exceeds the " + std::to_string(radiating_) +
                                   " radiating surfaces");
  if (c.row > 0)
    messages_.warn(control_line_, "row/col make View3D compute one row (or factor); the whole matrix is "
                              "computed and written here",
                   input_.warnings);
}

// ---- surfaces ---------------------------------------------------------------------------------

const char* kind_letter(SurfaceKind kind) {
  switch (kind) {
    case SurfaceKind::Radiating: return "S";
    case SurfaceKind::Mask: return "M";
    case SurfaceKind::Null: return "N";
    case SurfaceKind::Obstruction: return "O";
  }
  return "?";
}

// base, combination, emissivity and name: the fields after the geometry.
void Reader::common_fields(const Line& line, std::span<const std::string_view> fields, Surface& s) {
  const std::string who = "surface " + std::to_string(s.number);
  whole(line, fields[0], (who + ": base").c_str(), 0, 1 << 30, s.base);
  whole(line, fields[1], (who + ": combination").c_str(), 0, 1 << 30, s.combine);
  const auto e = to_number(fields[2]);
  if (!e || *e < 0 || *e > 1)
    messages_.error(line.number, who + ": the emissivity must be a number in [0, 1], got " + in_quotes(fields[2]));
  else
    s.emissivity = *e;
  if (fields[3].size() > kMaxNameBytes || !is_clean_utf8(fields[3]))
    messages_.error(line.number, who + ": the name must be UTF-8 text of at most " + std::to_string(kMaxNameBytes) +
                                     " bytes without control characters, got " + in_quotes(fields[3]));
  s.name = std::string(fields[3]);
}

void Reader::surface(const Line& line, SurfaceKind kind) {
  if (!geometry_) {
    messages_.error(line.number, "a surface before the F line (the geometry: F 3 or F 3a)");
    return;
  }
  const bool f3 = *geometry_ == Geometry::Vertices;
  const std::size_t corners_words = f3 ? 4 : 1;  // four vertex numbers, or a shape letter
  const std::size_t short_form = 2 + corners_words, long_form = short_form + 4;
  const bool obstruction = kind == SurfaceKind::Obstruction;
  const std::size_t n_words = line.words.size();
  Surface s;
  s.kind = kind;
  s.line = line.number;
  const long long expected = static_cast<long long>(input_.surfaces.size()) + 1;
  const auto n = line.words.size() > 1 ? to_whole(line.words[1]) : std::nullopt;
  if (!n || *n != expected) {
    messages_.error(line.number, "surface " + in_quotes(line.words.size() > 1 ? line.words[1] : "") +
                                     " out of sequence: expected " + std::to_string(expected));
    return;
  }
  s.number = static_cast<int>(*n);
  if (n_words != long_form && !(obstruction && n_words == short_form)) {
    const std::string shape = f3 ? "v1 v2 v3 v4" : "shape";
    messages_.error(line.number, std::string("expected '") + kind_letter(kind) + " n " + shape +
                                     (obstruction ? "' (base, combination, emissivity and name may follow)"
                                                  : " base cmb emit name'") +
                                     ", got " + std::to_string(n_words) + " words before any comment");
    input_.surfaces.push_back(std::move(s));  // keeps the numbering of the surfaces after it
    return;
  }
  const bool after_obstruction = !input_.surfaces.empty() && input_.surfaces.back().kind == SurfaceKind::Obstruction;
  if (!obstruction && after_obstruction) {
    messages_.error(line.number, "surface " + std::to_string(s.number) + " (" + kind_letter(kind) +
                                     ") follows an obstruction: View3D numbers the S, M and N surfaces first");
    return;
  }
  // A surface with a bad field is kept (the numbering goes on), and an F 3a one takes its numbers from
  // the next lines: the errors are reported, and no Input is made.
  if (f3) {
    for (std::size_t k = 0; k < 4; ++k) {
      int v = 0;
      const std::string what = "surface " + std::to_string(s.number) + ": vertex " + std::to_string(k + 1);
      if (!whole(line, line.words[2 + k], what.c_str(), k == 3 ? 0 : 1, 1 << 30, v)) continue;
      if (v > static_cast<int>(input_.vertices.size())) {
        messages_.error(line.number, what + " is " + std::to_string(v) + ", not defined before this line (" +
                                         std::to_string(input_.vertices.size()) + " vertices so far)");
      } else if (v > 0) {
        s.polygon.push_back(input_.vertices[v - 1]);
      }
    }
  } else {
    const char shape = static_cast<char>(std::toupper(static_cast<unsigned char>(line.words[2].front())));
    if (line.words[2].size() != 1 || (shape != 'R' && shape != 'Q' && shape != 'T')) {
      messages_.error(line.number, "surface " + std::to_string(s.number) + ": shape " + in_quotes(line.words[2]) +
                                       " is not R (rectangle), Q (quadrilateral) or T (triangle)");
    } else {
      pending_ = PendingBlast{input_.surfaces.size(), shape, {}, 5u + (shape == 'R' ? 2u : shape == 'T' ? 6u : 8u)};
    }
  }
  if (n_words == long_form) common_fields(line, std::span(line.words).subspan(short_form, 4), s);
  if (obstruction && (s.base != 0 || s.combine != 0))
    messages_.error(line.number, "obstruction " + std::to_string(s.number) + " can have neither a base nor a combination");
  if (obstruction) s.emissivity.reset();
  if (s.name.empty()) s.name = "obstruction-" + std::to_string(s.number);
  radiating_ += obstruction ? 0 : 1;
  input_.surfaces.push_back(std::move(s));
}

// ---- F 3a: the numbers that place a BLAST surface ------------------------------------------------

bool Reader::blast_numbers(const Line& line) {
  const Surface& s = input_.surfaces[pending_->surface];
  const std::string who = "surface " + std::to_string(s.number);
  if (!to_number(line.words.front())) {
    messages_.error(s.line, who + " needs " + std::to_string(pending_->needed) + " numbers on the lines after "
                            "it (origin x y z, azimuth, tilt, then its shape's); the file gives " +
                            std::to_string(pending_->numbers.size()));
    pending_.reset();
    return false;  // the line is a record of its own
  }
  for (std::string_view word : line.words) {
    const auto v = to_number(word);
    if (!v || pending_->numbers.size() == pending_->needed) {
      messages_.error(line.number, !v ? who + ": expected a number, got " + in_quotes(word)
                                      : who + ": more than the " + std::to_string(pending_->needed) +
                                            " numbers its shape takes");
      pending_.reset();
      return true;
    }
    pending_->numbers.push_back(*v);
  }
  if (pending_->numbers.size() == pending_->needed) {
    place_blast(*pending_, line.number);
    pending_.reset();
  }
  return true;
}

// View3D's GetVS3Da: a point (u, v) of the surface's own plane lies at
//   x = x0 − u cos a − v cos t sin a,   y = y0 + u sin a − v cos t cos a,   z = z0 + v sin t,
// a the azimuth (clockwise from north, +y), t the tilt (0 facing up, 90 vertical, 180 facing down).
// A rectangle w × h has the corners (0, h), (0, 0), (w, 0), (w, h) in that order.
void Reader::place_blast(const PendingBlast& p, int line) {
  Surface& s = input_.surfaces[p.surface];
  const double* q = p.numbers.data();
  for (int k = 0; k < 3; ++k)
    if (std::abs(q[k]) > 1e9) {
      messages_.error(line, "surface " + std::to_string(s.number) + ": |origin| exceeds 1e9");
      return;
    }
  const auto [sa, ca0] = sincos_degrees(q[3]);
  const auto [st, ct] = sincos_degrees(q[4]);
  const double ca = -ca0;
  std::vector<std::array<double, 2>> uv;
  if (p.shape == 'R') {
    if (!(q[5] > 0) || !(q[6] > 0)) {
      messages_.error(line, "surface " + std::to_string(s.number) + ": a rectangle's width and height must be > 0");
      return;
    }
    uv = {{0, q[6]}, {0, 0}, {q[5], 0}, {q[5], q[6]}};
  } else {
    for (std::size_t k = 5; k + 1 < p.needed; k += 2) uv.push_back({q[k], q[k + 1]});
  }
  for (const auto& [u, v] : uv) {
    if (std::abs(u) > 1e9 || std::abs(v) > 1e9) {
      messages_.error(line, "surface " + std::to_string(s.number) + ": a corner exceeds 1e9");
      return;
    }
    s.polygon.push_back({q[0] + u * ca - v * ct * sa, q[1] + u * sa + v * ct * ca, q[2] + v * st});
  }
}

}  // namespace

ReadResult read_vs3(std::string_view text, std::string_view name) { return Reader(name).run(text); }

}  // namespace lambert::vs3
