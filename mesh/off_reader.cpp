// OFF (Geomview's Object File Format), ascii: "[ST][C][N]OFF", then "nV nF [nE]", nV vertex lines
// "x y z" (followed by 2 texture coordinates with ST, 3 normal components with N and a colour of 3
// or 4 values with C, read and not used) and nF face lines "n i_1 ... i_n" (optionally followed by
// a colour of up to 4 values). '#' starts a comment anywhere. The counts are checked against the
// limits and against the bytes after them before anything is read.
#include <vector>

#include "mesh/mesh_text.h"

namespace lambert::mesh_io {
namespace {

struct Keyword {
  bool texture = false, colour = false, normal = false;
};

// The header keyword: [ST][C][N]OFF; 4OFF and nOFF (other dimensions) and binary OFF are refused.
std::optional<Keyword> parse_keyword(std::string_view word, std::string& problem) {
  Keyword k;
  std::string_view rest = word;
  if (rest.substr(0, 2) == "ST") k.texture = true, rest.remove_prefix(2);
  if (rest.substr(0, 1) == "C") k.colour = true, rest.remove_prefix(1);
  if (rest.substr(0, 1) == "N") k.normal = true, rest.remove_prefix(1);
  if (rest == "OFF") return k;
  if (rest == "4OFF" || rest == "nOFF")
    problem = in_quotes(word) + ": only three-dimensional OFF is supported";
  else
    problem = "not an OFF file (the header keyword is " + in_quotes(word) + ", expected OFF, COFF, NOFF, ...)";
  return std::nullopt;
}

// Lines with comments removed; blank ones are skipped.
class OffLines {
 public:
  explicit OffLines(std::string_view text) : lines_(text) {}
  bool next() {
    while (lines_.next()) {
      line_ = lines_.line().substr(0, lines_.line().find('#'));
      if (!Words(line_).at_end()) return true;
    }
    return false;
  }
  std::string_view line() const { return line_; }
  std::size_t number() const { return lines_.number(); }
  std::size_t remaining_bytes() const { return lines_.remaining_bytes(); }

 private:
  TextLines lines_;
  std::string_view line_;
};

std::optional<std::string> read_count(Words& words, const char* what, long long& count) {
  const auto w = words.next();
  if (!w) return "the header has no " + std::string(what) + " count";
  const auto n = parse_integer(*w, 0, 1LL << 62);
  if (!n) return "the " + std::string(what) + " count must be a whole number >= 0, got " + in_quotes(*w);
  count = *n;
  return std::nullopt;
}

std::optional<std::string> read_vertex(Words& words, const Keyword& k, PolygonMesh& m) {
  double c[3];
  std::size_t n = 0;
  while (auto w = words.next()) {
    const Real r = parse_real(*w);
    if (n < 3 && r.status == NumberStatus::NotFinite)
      return std::string("a coordinate is not finite (") + "xyz"[n] + " = " + std::string(*w) + ")";
    if (r.status != NumberStatus::Ok && (n < 3 || r.status != NumberStatus::NotFinite))
      return in_quotes(*w) + " is not a number";
    if (n < 3) c[n] = r.value;
    ++n;
  }
  const std::size_t extra = n < 3 ? 0 : n - 3, fixed = (k.texture ? 2 : 0) + (k.normal ? 3 : 0);
  const bool fits = k.colour ? (extra == fixed + 3 || extra == fixed + 4) : extra == fixed;
  if (n < 3 || !fits)
    return std::to_string(n) + " numbers; the header keyword asks for x y z" + (k.normal ? " nx ny nz" : "") +
           (k.colour ? " r g b [a]" : "") + (k.texture ? " s t" : "");
  m.vertices.push_back({c[0], c[1], c[2]});
  return std::nullopt;
}

std::optional<std::string> read_off_face(Words& words, PolygonMesh& m, std::vector<int>& corners,
                                         std::size_t line, const MeshReadLimits& limits) {
  const auto first = words.next();
  const auto n = first ? parse_integer(*first, 0, 1LL << 62) : std::nullopt;
  if (!n) return "a face line starts with its vertex count, got " + in_quotes(first.value_or(""));
  if (static_cast<unsigned long long>(*n) > limits.max_face_vertices)
    return "a face has " + std::to_string(*n) + " vertices; at most " + std::to_string(limits.max_face_vertices) +
           " are allowed";
  corners.clear();
  for (long long i = 0; i < *n; ++i) {
    const auto w = words.next();
    if (!w) return "the face has " + std::to_string(*n) + " vertices, the line ends after " + std::to_string(i);
    const auto v = parse_integer(*w, -(1LL << 31), (1LL << 31) - 1);
    if (!v) return "vertex index " + in_quotes(*w) + " is not a whole number";
    corners.push_back(static_cast<int>(*v));
  }
  std::size_t colour = 0;
  while (auto w = words.next()) {
    if (++colour > 4 || parse_real(*w).status != NumberStatus::Ok)
      return "after the face's indices only a colour (up to 4 numbers) may follow, got " + in_quotes(*w);
  }
  return add_face(m, corners.data(), corners.size(), m.vertices.size(), line, limits);
}

}  // namespace

PolygonMeshResult parse_off(std::string_view bytes, const MeshReadLimits& limits) {
  OffLines lines(bytes);
  if (!lines.next()) return failure("the file is empty");
  Words header(lines.line());
  std::string problem;
  const auto keyword = parse_keyword(*header.next(), problem);
  if (!keyword) return failure(at_line(lines.number(), problem));
  if (const auto w = Words(header).next(); w && *w == "BINARY")
    return failure(at_line(lines.number(), "binary OFF is not supported; write it as ascii"));
  Words counts = header;  // the counts may follow the keyword on its line
  if (counts.at_end()) {
    if (!lines.next()) return failure("the file ends before the vertex and face counts");
    counts = Words(lines.line());
  }
  long long nv = 0, nf = 0, ne = 0;
  for (auto [what, count] : {std::pair{"vertex", &nv}, std::pair{"face", &nf}})
    if (auto e = read_count(counts, what, *count)) return failure(at_line(lines.number(), *e));
  if (!counts.at_end()) {
    if (auto e = read_count(counts, "edge", ne)) return failure(at_line(lines.number(), *e));
    if (!counts.at_end()) return failure(at_line(lines.number(), "more than three counts"));
  }
  // "0 0 0\n" and "3 0 1 2\n" are the shortest vertex and face lines.
  if (auto e = check_count("vertices", nv, limits.max_vertices, lines.remaining_bytes(), 6))
    return failure(at_line(lines.number(), "the header " + *e));
  if (auto e = check_count("faces", nf, limits.max_faces, lines.remaining_bytes() - 6 * nv, 8))
    return failure(at_line(lines.number(), "the header " + *e));

  PolygonMeshResult result;
  PolygonMesh& m = result.mesh;
  m.vertices.reserve(nv);
  m.face_start.reserve(nf + 1);
  for (long long i = 0; i < nv; ++i) {
    if (!lines.next()) return failure("the file ends after " + std::to_string(i) + " of its " + std::to_string(nv) + " vertices");
    Words words(lines.line());
    if (auto e = read_vertex(words, *keyword, m))
      return failure(at_line(lines.number(), "vertex " + std::to_string(i) + ": " + *e));
  }
  std::vector<int> corners;
  for (long long i = 0; i < nf; ++i) {
    if (!lines.next()) return failure("the file ends after " + std::to_string(i) + " of its " + std::to_string(nf) + " faces");
    Words words(lines.line());
    if (auto e = read_off_face(words, m, corners, lines.number(), limits))
      return failure(at_line(lines.number(), "face " + std::to_string(i) + ": " + *e));
  }
  if (lines.next()) return failure(at_line(lines.number(), "data after the last face"));
  if (m.face_count() == 0) return failure("the file has no faces");
  return result;
}

}  // namespace lambert::mesh_io
