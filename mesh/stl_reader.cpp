// STL, binary and ascii. Binary: an 80-byte header, a little-endian uint32 facet count and 50 bytes
// a facet (normal, three corners as float32, a 16-bit attribute); a file is binary exactly when its
// size is 84 + 50 × that count. Ascii: "solid ... facet normal n n n / outer loop / vertex x y z
// (three times) / endloop / endfacet ... endsolid", keywords in any case, several solids in a
// file. STL repeats each corner per facet; corners at identical coordinates are welded into one
// vertex, in the order they first appear, so that facets that share an edge are connected.
#include <algorithm>
#include <bit>
#include <cctype>
#include <unordered_map>
#include <vector>

#include "mesh/mesh_text.h"

namespace lambert::mesh_io {
namespace {

constexpr std::size_t kBinaryHeaderBytes = 84, kBinaryFacetBytes = 50;

// Welds corners by their exact coordinates (-0 and 0 are the same point).
class Welder {
 public:
  explicit Welder(PolygonMesh& mesh) : mesh_(mesh) {}
  int index_of(const Point3& p) {
    const Key key{bits(p.x), bits(p.y), bits(p.z)};
    const auto [it, added] = index_.try_emplace(key, static_cast<int>(mesh_.vertices.size()));
    if (added) mesh_.vertices.push_back(p);
    return it->second;
  }

 private:
  struct Key {
    std::uint64_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      return std::hash<std::uint64_t>()(k.x) ^ (std::hash<std::uint64_t>()(k.y) * 0x9E3779B97F4A7C15ull) ^
             (std::hash<std::uint64_t>()(k.z) * 0xC2B2AE3D27D4EB4Full);
    }
  };
  static std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v == 0 ? 0.0 : v); }
  PolygonMesh& mesh_;
  std::unordered_map<Key, int, Hash> index_;
};

// A facet's three corners, checked and added.
std::optional<std::string> add_facet(const Point3 (&corner)[3], Welder& welder, PolygonMesh& m, std::size_t line,
                                     const MeshReadLimits& limits) {
  for (int c = 0; c < 3; ++c)
    if (auto e = check_finite(corner[c])) return "corner " + std::to_string(c + 1) + ": " + *e;
  int idx[3];
  for (int c = 0; c < 3; ++c) idx[c] = welder.index_of(corner[c]);
  if (m.vertices.size() > limits.max_vertices)
    return "more than " + std::to_string(limits.max_vertices) + " distinct vertices (the limit)";
  if (idx[0] == idx[1] || idx[1] == idx[2] || idx[0] == idx[2])
    return std::string("two of its corners are the same point (degenerate)");
  return add_face(m, idx, 3, m.vertices.size(), line, limits);
}

std::uint32_t load_u32(const char* p) {  // little-endian, whatever the machine's order
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  return std::uint32_t{b[0]} | std::uint32_t{b[1]} << 8 | std::uint32_t{b[2]} << 16 | std::uint32_t{b[3]} << 24;
}
float load_float(const char* p) { return std::bit_cast<float>(load_u32(p)); }

PolygonMeshResult parse_binary(std::string_view bytes, std::size_t facets, const MeshReadLimits& limits) {
  if (auto e = check_count("facets", facets, limits.max_faces, facets, 1)) return failure("the header " + *e);
  PolygonMeshResult result;
  PolygonMesh& m = result.mesh;
  m.face_start.reserve(facets + 1);
  Welder welder(m);
  for (std::size_t f = 0; f < facets; ++f) {
    const std::size_t at = kBinaryHeaderBytes + f * kBinaryFacetBytes;
    Point3 corner[3];
    for (int c = 0; c < 3; ++c) {
      const char* p = bytes.data() + at + 12 + 12 * c;  // after the normal
      corner[c] = {load_float(p), load_float(p + 4), load_float(p + 8)};
    }
    if (auto e = add_facet(corner, welder, m, 0, limits))
      return failure("facet " + std::to_string(f) + " (at byte " + std::to_string(at) + "): " + *e);
  }
  if (m.face_count() == 0) return failure("the file has no facets");
  return result;
}

bool keyword_is(std::string_view word, std::string_view keyword) {
  return word.size() == keyword.size() &&
         std::equal(word.begin(), word.end(), keyword.begin(),
                    [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

// The ascii grammar as a sequence of expected lines.
enum class Expect { SolidOrEnd, FacetOrEndsolid, OuterLoop, Vertex, EndLoop, EndFacet };

std::optional<std::string> expect_words(Words& words, std::initializer_list<std::string_view> keywords) {
  for (std::string_view k : keywords) {
    const auto w = words.next();
    if (!w || !keyword_is(*w, k)) return "expected '" + std::string(k) + "', got " + in_quotes(w.value_or(""));
  }
  return std::nullopt;
}

std::optional<std::string> read_numbers(Words& words, double (&v)[3], bool coordinates) {
  for (int a = 0; a < 3; ++a) {
    const auto w = words.next();
    const Real r = w ? parse_real(*w) : Real{};
    if (r.status == NumberStatus::NotFinite && coordinates) {
      v[a] = NAN;  // add_facet names the corner
      continue;
    }
    if (r.status != NumberStatus::Ok && !(r.status == NumberStatus::NotFinite && !coordinates))
      return "expected three numbers, got " + in_quotes(w.value_or(""));
    v[a] = r.value;
  }
  if (!words.at_end()) return std::string("more than three numbers");
  return std::nullopt;
}

PolygonMeshResult parse_ascii(std::string_view bytes, const MeshReadLimits& limits) {
  PolygonMeshResult result;
  PolygonMesh& m = result.mesh;
  Welder welder(m);
  TextLines lines(bytes);
  Expect expect = Expect::SolidOrEnd;
  Point3 corner[3];
  int corners = 0;
  std::size_t facet_line = 0;
  while (lines.next()) {
    Words words(lines.line());
    const auto first = Words(lines.line()).next();
    if (!first) continue;
    std::optional<std::string> problem;
    switch (expect) {
      case Expect::SolidOrEnd:
        problem = expect_words(words, {"solid"});  // the name is free text
        expect = Expect::FacetOrEndsolid;
        break;
      case Expect::FacetOrEndsolid:
        if (keyword_is(*first, "endsolid")) {
          expect = Expect::SolidOrEnd;
          break;
        }
        problem = expect_words(words, {"facet", "normal"});
        if (!problem) {
          double n[3];
          problem = read_numbers(words, n, false);
        }
        facet_line = lines.number();
        expect = Expect::OuterLoop;
        break;
      case Expect::OuterLoop:
        problem = expect_words(words, {"outer", "loop"});
        corners = 0;
        expect = Expect::Vertex;
        break;
      case Expect::Vertex: {
        double v[3] = {0, 0, 0};
        problem = expect_words(words, {"vertex"});
        if (!problem) problem = read_numbers(words, v, true);
        corner[corners++] = {v[0], v[1], v[2]};
        if (corners == 3) expect = Expect::EndLoop;
        break;
      }
      case Expect::EndLoop:
        problem = expect_words(words, {"endloop"});
        if (keyword_is(*first, "vertex")) problem = "a facet has more than 3 vertices; STL facets are triangles";
        expect = Expect::EndFacet;
        break;
      case Expect::EndFacet:
        problem = expect_words(words, {"endfacet"});
        if (!problem) {
          if (auto e = add_facet(corner, welder, m, facet_line, limits))
            problem = "facet " + std::to_string(m.face_count()) + ": " + *e;
        }
        expect = Expect::FacetOrEndsolid;
        break;
    }
    if (problem) return failure(at_line(lines.number(), *problem));
  }
  if (expect != Expect::SolidOrEnd)
    return failure("the file ends inside a solid (no 'endsolid' after line " + std::to_string(lines.number()) + ")");
  if (m.face_count() == 0) return failure("the file has no facets");
  return result;
}

}  // namespace

PolygonMeshResult parse_stl(std::string_view bytes, const MeshReadLimits& limits) {
  if (bytes.size() >= kBinaryHeaderBytes) {
    const std::uint32_t n = load_u32(bytes.data() + 80);
    if (bytes.size() == kBinaryHeaderBytes + kBinaryFacetBytes * std::uint64_t{n}) return parse_binary(bytes, n, limits);
  }
  Words first(bytes.substr(0, bytes.find('\n')));
  if (const auto w = first.next(); w && keyword_is(*w, "solid")) return parse_ascii(bytes, limits);
  std::string facets;
  if (bytes.size() >= kBinaryHeaderBytes) {
    const std::uint32_t n = load_u32(bytes.data() + 80);
    facets = "; as binary STL it declares " + std::to_string(n) + " facets, which take " +
             std::to_string(kBinaryHeaderBytes + kBinaryFacetBytes * std::uint64_t{n}) + " bytes";
  }
  return failure("not an STL file: it does not start with 'solid' (ascii) and its " + std::to_string(bytes.size()) +
                 " bytes do not match a binary STL's size" + facets);
}

}  // namespace lambert::mesh_io
