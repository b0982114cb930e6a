// The mesh readers' shared pieces (mesh/mesh_text.h), and parse_mesh, which picks the reader.
#include "mesh/mesh_text.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <cmath>
#include <vector>

namespace lambert::mesh_io {

bool TextLines::next() {
  if (pos_ >= text_.size()) return false;
  const std::size_t end = text_.find('\n', pos_);
  const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
  line_ = text_.substr(pos_, stop - pos_);
  if (!line_.empty() && line_.back() == '\r') line_.remove_suffix(1);
  pos_ = end == std::string_view::npos ? text_.size() : end + 1;
  ++number_;
  return true;
}

namespace {
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
}  // namespace

std::optional<std::string_view> Words::next() {
  std::size_t k = 0;
  while (k < rest_.size() && is_space(rest_[k])) ++k;
  if (k == rest_.size()) {
    rest_ = {};
    return std::nullopt;
  }
  std::size_t e = k;
  while (e < rest_.size() && !is_space(rest_[e])) ++e;
  const std::string_view word = rest_.substr(k, e - k);
  rest_.remove_prefix(e);
  return word;
}

bool Words::at_end() {
  std::size_t k = 0;
  while (k < rest_.size() && is_space(rest_[k])) ++k;
  rest_.remove_prefix(k);
  return rest_.empty();
}

Real parse_real(std::string_view word) {
  Real r;
  std::string_view digits = word;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);  // from_chars takes no '+'
  // MSVC's printf writes non-finite values as 1.#INF, 1.#QNAN, 1.#IND (with an optional sign).
  for (std::string_view msvc : {"#INF", "#QNAN", "#SNAN", "#IND"})
    if (digits.find(msvc) != std::string_view::npos) {
      r.status = NumberStatus::NotFinite;
      return r;
    }
  const char* end = digits.data() + digits.size();
  const auto [stop, ec] = std::from_chars(digits.data(), end, r.value, std::chars_format::general);
  if (ec == std::errc::result_out_of_range && stop == end) {
    // Out of range is also what from_chars says of an underflow (1e-400), which is zero.
    const std::size_t e = digits.find_first_of("eE");
    if (e != std::string_view::npos && e + 1 < digits.size() && digits[e + 1] == '-') {
      r.value = digits.front() == '-' ? -0.0 : 0.0;
      r.status = NumberStatus::Ok;
    } else {
      r.status = NumberStatus::OutOfRange;
    }
    return r;
  }
  if (ec != std::errc() || stop != end) return r;
  r.status = std::isfinite(r.value) ? NumberStatus::Ok : NumberStatus::NotFinite;
  return r;
}

std::optional<long long> parse_integer(std::string_view word, long long lo, long long hi) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  long long v = 0;
  const char* end = word.data() + word.size();
  const auto [stop, ec] = std::from_chars(word.data(), end, v);
  if (ec != std::errc() || stop != end || word.empty() || v < lo || v > hi) return std::nullopt;
  return v;
}

std::string in_quotes(std::string_view word) {
  constexpr std::size_t kMax = 40;
  std::string out(1, '\'');  // appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "'" + s
  out.append(word.substr(0, kMax));
  if (word.size() > kMax) out.append("...");
  out.push_back('\'');
  return out;
}

std::string at_line(std::size_t line, const std::string& message) {
  return "line " + std::to_string(line) + ": " + message;
}

std::optional<std::string> check_count(const char* what, unsigned long long declared, std::size_t limit,
                                       std::size_t bytes_left, std::size_t min_bytes_each) {
  if (declared > limit)
    return "declares " + std::to_string(declared) + " " + what + "; the limit is " + std::to_string(limit);
  if (min_bytes_each > 0 && declared > bytes_left / min_bytes_each)
    return "declares " + std::to_string(declared) + " " + what + ", but the " + std::to_string(bytes_left) +
           " bytes that follow can hold at most " + std::to_string(bytes_left / min_bytes_each);
  return std::nullopt;
}

std::optional<std::string> add_face(PolygonMesh& mesh, const int* indices, std::size_t count,
                                    std::size_t vertex_count, std::size_t line, const MeshReadLimits& limits,
                                    int index_base) {
  if (count < 3) return "a face needs at least 3 vertices, this one has " + std::to_string(count);
  if (count > limits.max_face_vertices)
    return "a face has " + std::to_string(count) + " vertices; at most " +
           std::to_string(limits.max_face_vertices) + " are allowed";
  if (mesh.face_count() >= limits.max_faces)
    return "more than " + std::to_string(limits.max_faces) + " faces (the limit)";
  for (std::size_t k = 0; k < count; ++k)
    if (indices[k] < 0 || static_cast<std::size_t>(indices[k]) >= vertex_count)
      return "vertex index " + std::to_string(indices[k] + index_base) + " is out of range (" +
             std::to_string(vertex_count) + " vertices)";
  std::optional<int> twice;
  if (count <= 16) {  // the common case, without allocating
    for (std::size_t i = 0; i < count && !twice; ++i)
      for (std::size_t j = i + 1; j < count; ++j)
        if (indices[i] == indices[j]) twice = indices[i];
  } else {
    std::vector<int> sorted(indices, indices + count);
    std::sort(sorted.begin(), sorted.end());
    if (const auto it = std::adjacent_find(sorted.begin(), sorted.end()); it != sorted.end()) twice = *it;
  }
  if (twice) return "the face uses vertex " + std::to_string(*twice + index_base) + " twice (degenerate)";
  mesh.indices.insert(mesh.indices.end(), indices, indices + count);
  mesh.face_start.push_back(mesh.indices.size());
  mesh.face_line.push_back(line);
  return std::nullopt;
}

std::optional<std::string> check_finite(const Point3& p) {
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(p[a]))
      return std::string("a coordinate is not finite (") + "xyz"[a] + " = " +
             (std::isnan(p[a]) ? "nan" : p[a] > 0 ? "inf" : "-inf") + ")";
  return std::nullopt;
}

}  // namespace lambert::mesh_io

namespace lambert {

std::optional<MeshFormat> mesh_format_of(std::string_view path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".off") return MeshFormat::Off;
  if (ext == ".stl") return MeshFormat::Stl;
  return std::nullopt;
}

PolygonMeshResult parse_mesh(std::string_view bytes, MeshFormat format, const MeshReadLimits& limits) {
  switch (format) {
    case MeshFormat::Obj: return mesh_io::parse_obj(bytes, limits);
    case MeshFormat::Ply: return mesh_io::parse_ply(bytes, limits);
    case MeshFormat::Off: return mesh_io::parse_off(bytes, limits);
    case MeshFormat::Stl: return mesh_io::parse_stl(bytes, limits);
  }
  return mesh_io::failure("unknown format");
}

}  // namespace lambert
