// What the mesh readers (obj_reader.cpp, ply_reader.cpp, off_reader.cpp, stl_reader.cpp) share:
// a line cursor over a text file, strict number parsing, and the checks every reader makes on
// what it read. The public interface is mesh/mesh_file.h; the photometric file readers
// (solver/photometry/) use the line cursor and the number parsing too, so that every file Lambert
// reads parses its numbers the same way.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "mesh/mesh_file.h"

namespace lambert::mesh_io {

// The lines of a text, numbered from 1, without their "\n" or "\r\n".
class TextLines {
 public:
  explicit TextLines(std::string_view text) : text_(text) {}
  // Moves to the next line; false at the end of the text.
  bool next();
  std::string_view line() const { return line_; }
  std::size_t number() const { return number_; }
  // Bytes after the current line: what later elements can occupy.
  std::size_t remaining_bytes() const { return text_.size() - pos_; }
  std::size_t offset() const { return pos_; }  // of the byte after the current line

 private:
  std::string_view text_;
  std::string_view line_;
  std::size_t pos_ = 0, number_ = 0;
};

// Whitespace-separated words of one line (spaces, tabs, a stray '\r').
class Words {
 public:
  explicit Words(std::string_view line) : rest_(line) {}
  std::optional<std::string_view> next();
  bool at_end();  // no word left

 private:
  std::string_view rest_;
};

// Why a word is not the number a reader wanted.
enum class NumberStatus { Ok, NotANumber, OutOfRange, NotFinite };

struct Real {
  double value = 0;
  NumberStatus status = NumberStatus::NotANumber;
};

// A decimal floating-point number, the whole word (an optional leading '+' allowed). "nan", "inf"
// and MSVC's "1.#INF" / "-1.#IND" are NotFinite; 1e400 is OutOfRange.
Real parse_real(std::string_view word);

// A decimal integer, the whole word, in [lo, hi].
std::optional<long long> parse_integer(std::string_view word, long long lo, long long hi);

// "'word'" for messages, cut to 40 bytes.
std::string in_quotes(std::string_view word);

// "line N: message".
std::string at_line(std::size_t line, const std::string& message);

// Checks a declared element count against the limit and against the bytes that must hold it (each
// element takes at least min_bytes_each); on failure the message says which bound it exceeds.
std::optional<std::string> check_count(const char* what, unsigned long long declared, std::size_t limit,
                                       std::size_t bytes_left, std::size_t min_bytes_each);

// Appends a face (0-based vertex indices) to `mesh` after checking its size, the face limit, its
// indices and that no index repeats. Returns the error, without a line prefix; messages show
// indices as the file numbers them (index_base 1 for OBJ).
std::optional<std::string> add_face(PolygonMesh& mesh, const int* indices, std::size_t count,
                                    std::size_t vertex_count, std::size_t line, const MeshReadLimits& limits,
                                    int index_base = 0);

// "a coordinate is not finite (x = nan)" for a point with a NaN or infinite coordinate, else nullopt.
std::optional<std::string> check_finite(const Point3& p);

// The format parsers (parse_mesh dispatches to them).
PolygonMeshResult parse_obj(std::string_view bytes, const MeshReadLimits& limits);
PolygonMeshResult parse_ply(std::string_view bytes, const MeshReadLimits& limits);
PolygonMeshResult parse_off(std::string_view bytes, const MeshReadLimits& limits);
PolygonMeshResult parse_stl(std::string_view bytes, const MeshReadLimits& limits);

inline PolygonMeshResult failure(std::string message) {
  PolygonMeshResult r;
  r.error = std::move(message);
  return r;
}

}  // namespace lambert::mesh_io
