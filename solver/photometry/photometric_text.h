// What the photometric readers (ies_reader.cpp, ldt_reader.cpp) share: a failure that names its
// line, a word cursor over the numeric part of a file, and strict field parsers. Internal to
// solver/photometry/; the public interface is photometric_data.h. The number syntax and the line
// splitting are the mesh readers' (mesh/mesh_text.h), so every file Lambert reads parses numbers
// the same way.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "solver/photometry/photometric_data.h"

namespace lambert::photometry_io {

// Thrown inside a reader and caught at its entry point, which prefixes the file's name.
struct ReadFailure {
  std::size_t line = 0;  // 0: the file as a whole
  std::string message;
};
[[noreturn]] void fail(std::size_t line, std::string message);

// "NAME: line N: message" (or "NAME: message" for line 0).
std::string located(std::string_view name, std::size_t line, const std::string& message);

// The text without white space at either end (a header's or a keyword's value).
std::string_view trimmed(std::string_view s);

// The words of a text from a byte offset on, separated by white space and, where commas_separate,
// by commas (LM-63 allows both), with the line each one is on.
class WordCursor {
 public:
  WordCursor(std::string_view text, std::size_t offset, std::size_t line, bool commas_separate)
      : text_(text), pos_(offset), line_(line), commas_(commas_separate) {}
  // The next word, or nullopt at the end of the text.
  std::optional<std::string_view> next();
  std::size_t line() const { return line_; }  // of the word last returned (or of the end)
  std::size_t remaining_bytes() const { return text_.size() - pos_; }

 private:
  bool separator(char c) const;
  std::string_view text_;
  std::size_t pos_;
  std::size_t line_;
  bool commas_;
};

// A decimal number that must be finite: "field: 'x' is not a number" and the like otherwise.
double real_field(std::string_view word, std::size_t line, std::string_view field);
// The same where EULUMDAT's decimal comma ("12,5") is allowed.
double real_field_decimal_comma(std::string_view word, std::size_t line, std::string_view field);
// A decimal integer in [lo, hi].
long long integer_field(std::string_view word, std::size_t line, std::string_view field, long long lo, long long hi);

// The next word of the cursor, or a failure naming what was missing ("the file ends before field").
std::string_view next_word(WordCursor& words, std::string_view field);
// The next word as a finite number or an integer in [lo, hi], failing at the line it is on.
double next_real(WordCursor& words, std::string_view field);
long long next_integer(WordCursor& words, std::string_view field, long long lo, long long hi);

// A count a file declares, checked against the limit and against the bytes that follow (each value
// takes at least min_bytes_each) before anything is allocated.
void check_declared(std::size_t line, std::string_view what, long long declared, std::size_t limit,
                    std::size_t bytes_left, std::size_t min_bytes_each);

// Angles strictly ascending (lines: where each one was read).
void check_ascending(const std::vector<double>& angles, const std::vector<std::size_t>& lines, std::string_view what);

// The shortest form of a number for messages ("45", "-2.5").
std::string number_text(double v);

// ---- LM-63 rules (ies_rules.cpp) ----

// The luminous opening from LM-63's width, length and height (metres, signs as written), by the
// version's table: LM-63-2002 and 2019 Table 1 (negative dimensions: circles, cylinders, spheres);
// LM-63-1995 and earlier encode a disk, a vertical cylinder and a sphere by a negative width with
// length 0. Fails naming `line` where the signs match no shape.
LuminousDimensions ies_opening(int year, double width, double length, double height, std::size_t line);

// The angle ranges LM-63 allows for each photometric type (first and last angles; every angle is
// already ascending); fails at the line of the offending list.
void check_ies_ranges(PhotometryType type, const std::vector<double>& vertical, const std::vector<double>& horizontal,
                      std::size_t vertical_line, std::size_t horizontal_line);

}  // namespace lambert::photometry_io
