// The photometric readers' shared pieces (photometric_text.h).
#include "solver/photometry/photometric_text.h"

#include <cctype>
#include <charconv>
#include <utility>

#include "mesh/mesh_text.h"

namespace lambert::photometry_io {

void fail(std::size_t line, std::string message) { throw ReadFailure{line, std::move(message)}; }

std::string located(std::string_view name, std::size_t line, const std::string& message) {
  std::string out(name);
  out += ": ";
  if (line > 0) out += "line " + std::to_string(line) + ": ";
  return out + message;
}

std::string_view trimmed(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

bool WordCursor::separator(char c) const {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v' || (commas_ && c == ',');
}

std::optional<std::string_view> WordCursor::next() {
  while (pos_ < text_.size() && separator(text_[pos_])) {
    if (text_[pos_] == '\n') ++line_;
    ++pos_;
  }
  if (pos_ >= text_.size()) return std::nullopt;
  const std::size_t start = pos_;
  while (pos_ < text_.size() && !separator(text_[pos_])) ++pos_;
  return text_.substr(start, pos_ - start);
}

namespace {

std::string field_prefix(std::string_view field) { return std::string(field) + ": "; }

double checked_real(std::string_view word, std::size_t line, std::string_view field) {
  const mesh_io::Real r = mesh_io::parse_real(word);
  switch (r.status) {
    case mesh_io::NumberStatus::Ok: return r.value;
    case mesh_io::NumberStatus::NotFinite:
      fail(line, field_prefix(field) + mesh_io::in_quotes(word) + " is not a finite number");
    case mesh_io::NumberStatus::OutOfRange:
      fail(line, field_prefix(field) + mesh_io::in_quotes(word) + " is out of the range of a double");
    case mesh_io::NumberStatus::NotANumber: break;
  }
  fail(line, field_prefix(field) + "expected a number, got " + mesh_io::in_quotes(word));
}

}  // namespace

double real_field(std::string_view word, std::size_t line, std::string_view field) {
  return checked_real(word, line, field);
}

double real_field_decimal_comma(std::string_view word, std::size_t line, std::string_view field) {
  const std::size_t comma = word.find(',');
  if (comma == std::string_view::npos || word.find('.') != std::string_view::npos ||
      word.find(',', comma + 1) != std::string_view::npos)
    return checked_real(word, line, field);
  std::string dotted(word);
  dotted[comma] = '.';
  return checked_real(dotted, line, field);
}

long long integer_field(std::string_view word, std::size_t line, std::string_view field, long long lo, long long hi) {
  if (auto v = mesh_io::parse_integer(word, lo, hi)) return *v;
  long long any = 0;
  std::string_view digits = word;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  const auto [stop, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), any);
  if (ec == std::errc() && stop == digits.data() + digits.size() && !digits.empty())
    fail(line, field_prefix(field) + std::to_string(any) + " is outside [" + std::to_string(lo) + ", " +
                   std::to_string(hi) + "]");
  fail(line, field_prefix(field) + "expected an integer, got " + mesh_io::in_quotes(word));
}

std::string_view next_word(WordCursor& words, std::string_view field) {
  if (auto w = words.next()) return *w;
  fail(words.line(), "the file ends before " + std::string(field));
}

double next_real(WordCursor& words, std::string_view field) {
  const std::string_view word = next_word(words, field);  // moves the cursor to the word's line
  return real_field(word, words.line(), field);
}

long long next_integer(WordCursor& words, std::string_view field, long long lo, long long hi) {
  const std::string_view word = next_word(words, field);
  return integer_field(word, words.line(), field, lo, hi);
}

void check_declared(std::size_t line, std::string_view what, long long declared, std::size_t limit,
                    std::size_t bytes_left, std::size_t min_bytes_each) {
  if (auto problem = mesh_io::check_count(std::string(what).c_str(), static_cast<unsigned long long>(declared),
                                          limit, bytes_left, min_bytes_each))
    fail(line, *problem);
}

void check_ascending(const std::vector<double>& angles, const std::vector<std::size_t>& lines, std::string_view what) {
  for (std::size_t k = 1; k < angles.size(); ++k)
    if (!(angles[k] > angles[k - 1]))
      fail(lines[k], std::string(what) + " " + std::to_string(k + 1) + ": " + number_text(angles[k]) +
                         " does not follow " + number_text(angles[k - 1]) + " in ascending order");
}

std::string number_text(double v) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
  return ec == std::errc() ? std::string(buffer, end) : std::to_string(v);
}

}  // namespace lambert::photometry_io
