// PLY (Greg Turk's polygon file format, 1994): ascii, binary_little_endian and binary_big_endian.
// The `vertex` element's x, y, z (of any numeric type) and the `face` element's `vertex_indices`
// (or `vertex_index`) list are read; other elements are read past. The header is bounded
// (kMaxHeaderBytes), and every element count is checked against the limits and against the bytes
// after the header before any element is read.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <vector>

#include "mesh/mesh_text.h"

namespace lambert::mesh_io {
namespace {

constexpr std::size_t kMaxHeaderBytes = 64 * 1024;

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct TypeInfo {
  std::string_view names[2];
  PlyType type;
  std::size_t bytes;
  long long lo, hi;  // integer range (unused for floats)
};
constexpr TypeInfo kTypes[] = {
    {{"char", "int8"}, PlyType::Int8, 1, -128, 127},
    {{"uchar", "uint8"}, PlyType::UInt8, 1, 0, 255},
    {{"short", "int16"}, PlyType::Int16, 2, -32768, 32767},
    {{"ushort", "uint16"}, PlyType::UInt16, 2, 0, 65535},
    {{"int", "int32"}, PlyType::Int32, 4, -2147483648LL, 2147483647LL},
    {{"uint", "uint32"}, PlyType::UInt32, 4, 0, 4294967295LL},
    {{"float", "float32"}, PlyType::Float32, 4, 0, 0},
    {{"double", "float64"}, PlyType::Float64, 8, 0, 0},
};

const TypeInfo& info(PlyType t) { return kTypes[static_cast<int>(t)]; }
bool is_integer(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

std::optional<PlyType> type_named(std::string_view name) {
  for (const TypeInfo& t : kTypes)
    if (name == t.names[0] || name == t.names[1]) return t.type;
  return std::nullopt;
}

struct Property {
  std::string name;
  bool list = false;
  PlyType count_type = PlyType::UInt8, type = PlyType::Float32;
};

struct Element {
  std::string name;
  unsigned long long count = 0;
  std::vector<Property> properties;
  std::size_t line = 0;  // of its "element" line
  // The fewest bytes one instance can take: a digit and a separator per value in ascii.
  std::size_t min_bytes(PlyEncoding e) const {
    std::size_t n = 0;
    for (const Property& p : properties)
      n += e == PlyEncoding::Ascii ? 2 : info(p.list ? p.count_type : p.type).bytes;
    return n;
  }
};

struct Header {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<Element> elements;
};

// Roles the reader gives to properties: the vertex coordinates and the face list.
struct Layout {
  int vertex_element = -1, face_element = -1;
  int xyz[3] = {-1, -1, -1};  // property indices in the vertex element
  int face_list = -1;         // property index in the face element
};

std::optional<std::string> read_property(Words& words, Element& e) {
  Property p;
  auto first = words.next();
  if (!first) return std::string("a property needs a type and a name");
  if (*first == "list") {
    const auto ct = words.next(), vt = words.next();
    const auto count_type = ct ? type_named(*ct) : std::nullopt;
    const auto type = vt ? type_named(*vt) : std::nullopt;
    if (!count_type || !type) return std::string("'property list' needs a count type and a value type (e.g. uchar int)");
    if (!is_integer(*count_type)) return std::string("a list's count type must be an integer type");
    p.list = true, p.count_type = *count_type, p.type = *type;
  } else {
    const auto type = type_named(*first);
    if (!type) return "unknown property type " + in_quotes(*first);
    p.type = *type;
  }
  const auto name = words.next();
  if (!name || !words.at_end()) return std::string("a property line ends with the property's name");
  for (const Property& q : e.properties)
    if (q.name == *name) return "property " + in_quotes(*name) + " is declared twice";
  p.name = std::string(*name);
  e.properties.push_back(std::move(p));
  return std::nullopt;
}

// Reads the header up to end_header; `lines` is left on the end_header line.
std::optional<std::string> read_header(TextLines& lines, Header& h) {
  if (!lines.next() || lines.line() != "ply") return std::string("not a PLY file (the first line is not 'ply')");
  bool format_seen = false;
  while (lines.next()) {
    if (lines.offset() > kMaxHeaderBytes)
      return "no 'end_header' line in the first " + std::to_string(kMaxHeaderBytes) + " bytes";
    Words words(lines.line());
    const auto key = words.next();
    auto at = [&](const std::string& m) { return std::optional<std::string>(at_line(lines.number(), m)); };
    if (!key || *key == "comment" || *key == "obj_info") continue;
    if (*key == "end_header") {
      if (!format_seen) return at("the header has no 'format' line");
      return std::nullopt;
    }
    if (*key == "format") {
      const auto enc = words.next(), version = words.next();
      if (!enc || !version || *version != "1.0" || !words.at_end()) return at("expected 'format ENCODING 1.0'");
      if (*enc == "ascii") h.encoding = PlyEncoding::Ascii;
      else if (*enc == "binary_little_endian") h.encoding = PlyEncoding::BinaryLittleEndian;
      else if (*enc == "binary_big_endian") h.encoding = PlyEncoding::BinaryBigEndian;
      else return at("unknown encoding " + in_quotes(*enc));
      format_seen = true;
    } else if (*key == "element") {
      const auto name = words.next(), count = words.next();
      if (!name || !count || !words.at_end()) return at("expected 'element NAME COUNT'");
      const auto n = parse_integer(*count, 0, (1LL << 62));
      if (!n) return at("element " + in_quotes(*name) + ": the count " + in_quotes(*count) + " is not a whole number >= 0");
      for (const Element& e : h.elements)
        if (e.name == *name) return at("element " + in_quotes(*name) + " is declared twice");
      h.elements.push_back({std::string(*name), static_cast<unsigned long long>(*n), {}, lines.number()});
    } else if (*key == "property") {
      if (h.elements.empty()) return at("a property before any element");
      if (auto e = read_property(words, h.elements.back())) return at(*e);
    } else {
      return at("unknown header line " + in_quotes(*key));
    }
  }
  return std::string("the header has no 'end_header' line");
}

std::optional<std::string> find_layout(const Header& h, Layout& layout) {
  for (std::size_t k = 0; k < h.elements.size(); ++k) {
    const Element& e = h.elements[k];
    auto at = [&](const std::string& m) { return std::optional<std::string>(at_line(e.line, m)); };
    if (e.properties.empty() && e.count > 0) return at("element " + in_quotes(e.name) + " has no properties");
    if (e.name == "tristrips") return at("triangle strips ('tristrips') are not supported; export faces");
    if (e.name == "vertex") {
      layout.vertex_element = static_cast<int>(k);
      for (std::size_t p = 0; p < e.properties.size(); ++p)
        for (int a = 0; a < 3; ++a)
          if (e.properties[p].name == std::string_view("xyz").substr(a, 1)) {
            if (e.properties[p].list) return at(std::string("vertex property ") + "xyz"[a] + " must not be a list");
            layout.xyz[a] = static_cast<int>(p);
          }
      for (int a = 0; a < 3; ++a)
        if (layout.xyz[a] < 0) return at(std::string("the vertex element has no ") + "xyz"[a] + " property");
    } else if (e.name == "face") {
      if (layout.vertex_element < 0) return at("the face element must come after the vertex element");
      layout.face_element = static_cast<int>(k);
      for (std::size_t p = 0; p < e.properties.size(); ++p)
        if (e.properties[p].name == "vertex_indices" || e.properties[p].name == "vertex_index")
          layout.face_list = static_cast<int>(p);
      if (layout.face_list < 0) return at("the face element has no 'vertex_indices' list");
      const Property& list = e.properties[layout.face_list];
      if (!list.list || !is_integer(list.type)) return at("'" + list.name + "' must be a list of integers");
    }
  }
  if (layout.vertex_element < 0) return std::string("the header declares no vertex element");
  if (layout.face_element < 0) return std::string("the header declares no face element: the file has no faces");
  return std::nullopt;
}

std::optional<std::string> check_counts(const Header& h, const Layout& layout, std::size_t body_bytes,
                                        const MeshReadLimits& limits) {
  std::size_t left = body_bytes;
  for (std::size_t k = 0; k < h.elements.size(); ++k) {
    const Element& e = h.elements[k];
    const std::size_t limit = static_cast<int>(k) == layout.vertex_element ? limits.max_vertices
                              : static_cast<int>(k) == layout.face_element ? limits.max_faces
                                                                           : std::size_t(-1);
    const std::size_t each = e.min_bytes(h.encoding);
    const std::string what = e.name == "vertex" ? "vertices" : e.name == "face" ? "faces" : "'" + e.name + "' elements";
    if (auto problem = check_count(what.c_str(), e.count, limit, left, each))
      return at_line(e.line, "element " + e.name + " " + *problem);
    left -= e.count * each;
  }
  return std::nullopt;
}

// ---- ascii data ---------------------------------------------------------------------------------

// One value of type t from an ascii word: integers must be whole numbers in the type's range; a
// float may be non-finite (NaN for MSVC's 1.#IND): the caller decides whether it may be.
std::optional<double> ascii_value(std::string_view word, PlyType t, std::string& problem) {
  if (is_integer(t)) {
    const auto v = parse_integer(word, info(t).lo, info(t).hi);
    if (!v) problem = in_quotes(word) + " is not a whole number in the range of " + std::string(info(t).names[0]);
    return v ? std::optional<double>(static_cast<double>(*v)) : std::nullopt;
  }
  const Real r = parse_real(word);
  if (r.status == NumberStatus::Ok) return r.value;
  if (r.status == NumberStatus::NotFinite) return std::isnan(r.value) || std::isinf(r.value) ? r.value : NAN;
  problem = in_quotes(word) + (r.status == NumberStatus::OutOfRange ? " is out of the double range" : " is not a number");
  return std::nullopt;
}

// A face index as an int, clamped so that a value beyond int's range stays out of range.
int to_index(double v) { return static_cast<int>(std::clamp(v, -2147483648.0, 2147483647.0)); }

struct Sink {
  PolygonMesh& mesh;
  const Layout& layout;
  const MeshReadLimits& limits;
  std::vector<int> corners;
};

std::optional<std::string> read_ascii_element(Words& words, const Element& e, int element, std::size_t line,
                                              Sink& sink) {
  const bool is_vertex = element == sink.layout.vertex_element, is_face = element == sink.layout.face_element;
  Point3 p;
  double* xyz[3] = {&p.x, &p.y, &p.z};
  for (std::size_t k = 0; k < e.properties.size(); ++k) {
    const Property& prop = e.properties[k];
    std::string problem;
    std::size_t items = 1;
    if (prop.list) {
      const auto w = words.next();
      if (!w) return "expected " + std::to_string(e.properties.size()) + " properties, the line ends before " + in_quotes(prop.name);
      const auto n = ascii_value(*w, prop.count_type, problem);
      if (!n) return prop.name + " count: " + problem;
      items = static_cast<std::size_t>(*n);
      if (is_face && static_cast<int>(k) == sink.layout.face_list && items > sink.limits.max_face_vertices)
        return "a face has " + std::to_string(items) + " vertices; at most " +
               std::to_string(sink.limits.max_face_vertices) + " are allowed";
      sink.corners.clear();
    }
    for (std::size_t i = 0; i < items; ++i) {
      const auto w = words.next();
      if (!w) return "the line ends inside property " + in_quotes(prop.name);
      const auto v = ascii_value(*w, prop.type, problem);
      if (!v) return prop.name + ": " + problem;
      if (is_vertex)
        for (int a = 0; a < 3; ++a)
          if (static_cast<int>(k) == sink.layout.xyz[a]) *xyz[a] = *v;
      if (is_face && static_cast<int>(k) == sink.layout.face_list)
        sink.corners.push_back(to_index(*v));
    }
  }
  if (!words.at_end()) return std::string("more values than the element's properties");
  if (is_vertex) {
    if (auto e2 = check_finite(p)) return e2;
    sink.mesh.vertices.push_back(p);
  }
  if (is_face)
    return add_face(sink.mesh, sink.corners.data(), sink.corners.size(), sink.mesh.vertices.size(), line,
                    sink.limits);
  return std::nullopt;
}

std::optional<std::string> read_ascii(TextLines& lines, const Header& h, Sink& sink) {
  for (std::size_t k = 0; k < h.elements.size(); ++k) {
    const Element& e = h.elements[k];
    for (unsigned long long i = 0; i < e.count; ++i) {
      do {
        if (!lines.next())
          return "the file ends after " + std::to_string(i) + " of the " + std::to_string(e.count) + " " + e.name +
                 " elements";
      } while (Words(lines.line()).at_end());
      Words words(lines.line());
      if (auto problem = read_ascii_element(words, e, static_cast<int>(k), lines.number(), sink))
        return at_line(lines.number(), e.name + " " + std::to_string(i) + ": " + *problem);
    }
  }
  while (lines.next())
    if (!Words(lines.line()).at_end()) return at_line(lines.number(), "data after the last element");
  return std::nullopt;
}

// ---- binary data --------------------------------------------------------------------------------

class BinaryCursor {
 public:
  BinaryCursor(std::string_view bytes, std::size_t pos, bool big_endian)
      : bytes_(bytes), pos_(pos), big_(big_endian) {}
  std::size_t pos() const { return pos_; }
  std::size_t left() const { return bytes_.size() - pos_; }
  // Reads one value of type t; false when the file ends first.
  bool read(PlyType t, double& value) {
    const std::size_t n = info(t).bytes;
    if (left() < n) return false;
    unsigned char b[8];
    std::memcpy(b, bytes_.data() + pos_, n);
    pos_ += n;
    if (big_ != (std::endian::native == std::endian::big)) std::reverse(b, b + n);
    switch (t) {
      case PlyType::Int8: value = static_cast<std::int8_t>(b[0]); break;
      case PlyType::UInt8: value = b[0]; break;
      case PlyType::Int16: value = load<std::int16_t>(b); break;
      case PlyType::UInt16: value = load<std::uint16_t>(b); break;
      case PlyType::Int32: value = load<std::int32_t>(b); break;
      case PlyType::UInt32: value = load<std::uint32_t>(b); break;
      case PlyType::Float32: value = load<float>(b); break;
      case PlyType::Float64: value = load<double>(b); break;
    }
    return true;
  }
  void skip(std::size_t n) { pos_ += n; }

 private:
  template <typename T>
  static T load(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof v);
    return v;
  }
  std::string_view bytes_;
  std::size_t pos_;
  bool big_;
};

std::optional<std::string> read_binary_element(BinaryCursor& in, const Element& e, int element, Sink& sink) {
  const bool is_vertex = element == sink.layout.vertex_element, is_face = element == sink.layout.face_element;
  Point3 p;
  double* xyz[3] = {&p.x, &p.y, &p.z};
  constexpr const char* ends = "the file ends inside it";
  for (std::size_t k = 0; k < e.properties.size(); ++k) {
    const Property& prop = e.properties[k];
    double v = 0;
    if (!prop.list) {
      if (!in.read(prop.type, v)) return std::string(ends);
      if (is_vertex)
        for (int a = 0; a < 3; ++a)
          if (static_cast<int>(k) == sink.layout.xyz[a]) *xyz[a] = v;
      continue;
    }
    double count = 0;
    if (!in.read(prop.count_type, count)) return std::string(ends);
    if (count < 0) return "a list count of " + std::to_string(static_cast<long long>(count));
    const auto items = static_cast<std::size_t>(count);
    const bool face_list = is_face && static_cast<int>(k) == sink.layout.face_list;
    if (face_list && items > sink.limits.max_face_vertices)
      return "a face has " + std::to_string(items) + " vertices; at most " +
             std::to_string(sink.limits.max_face_vertices) + " are allowed";
    if (items > in.left() / info(prop.type).bytes)
      return "a list of " + std::to_string(items) + " values, but only " + std::to_string(in.left()) +
             " bytes are left";
    if (!face_list) {
      in.skip(items * info(prop.type).bytes);
      continue;
    }
    sink.corners.clear();
    for (std::size_t i = 0; i < items; ++i) {
      in.read(prop.type, v);
      sink.corners.push_back(to_index(v));
    }
  }
  if (is_vertex) {
    if (auto problem = check_finite(p)) return problem;
    sink.mesh.vertices.push_back(p);
  }
  if (is_face)
    return add_face(sink.mesh, sink.corners.data(), sink.corners.size(), sink.mesh.vertices.size(), 0,
                    sink.limits);
  return std::nullopt;
}

std::optional<std::string> read_binary(BinaryCursor& in, const Header& h, Sink& sink) {
  for (std::size_t k = 0; k < h.elements.size(); ++k) {
    const Element& e = h.elements[k];
    for (unsigned long long i = 0; i < e.count; ++i) {
      const std::size_t start = in.pos();
      if (auto problem = read_binary_element(in, e, static_cast<int>(k), sink))
        return e.name + " " + std::to_string(i) + " (at byte " + std::to_string(start) + "): " + *problem;
    }
  }
  if (in.left() > 0)
    return std::to_string(in.left()) + " bytes after the last element (the header's counts do not match the file)";
  return std::nullopt;
}

}  // namespace

PolygonMeshResult parse_ply(std::string_view bytes, const MeshReadLimits& limits) {
  TextLines lines(bytes);
  Header header;
  if (auto problem = read_header(lines, header)) return failure(*problem);
  Layout layout;
  if (auto problem = find_layout(header, layout)) return failure(*problem);
  if (auto problem = check_counts(header, layout, lines.remaining_bytes(), limits)) return failure(*problem);

  PolygonMeshResult result;
  const Element& vertices = header.elements[layout.vertex_element];
  const Element& faces = header.elements[layout.face_element];
  result.mesh.vertices.reserve(vertices.count);  // bounded by check_counts
  result.mesh.face_start.reserve(faces.count + 1);
  Sink sink{result.mesh, layout, limits, {}};
  std::optional<std::string> problem;
  if (header.encoding == PlyEncoding::Ascii) {
    problem = read_ascii(lines, header, sink);
  } else {
    BinaryCursor in(bytes, lines.offset(), header.encoding == PlyEncoding::BinaryBigEndian);
    problem = read_binary(in, header, sink);
  }
  if (problem) return failure(*problem);
  if (result.mesh.face_count() == 0) return failure("the file has no faces");
  return result;
}

}  // namespace lambert::mesh_io
