// IES LM-63 files, versions 1986 (no version line), 1991 ("IESNA91"), 1995 ("IESNA:LM-63-1995"),
// 2002 ("IESNA:LM-63-2002") and 2019 ("IES:LM-63-2019") (photometric_data.h).
//
// Layout: the version line, keyword lines "[KEYWORD] text" (free label lines in 1986) up to the line
// "TILT=NONE" or "TILT=INCLUDE" (then the lamp-to-luminaire geometry, the number of tilt angles, the
// angles and their multiplying factors), then numbers separated by white space or commas:
//   lamps, lumens per lamp (−1: absolute photometry), candela multiplier, vertical angles,
//   horizontal angles, photometric type (1 C, 2 B, 3 A), units (1 feet, 2 metres), width, length,
//   height; ballast factor, a factor (1986/1991: ballast-lamp photometric factor; 1995/2002: unused;
//   2019: the file-generation type), input watts; the vertical angles, the horizontal angles, and
//   per horizontal angle one candela value per vertical angle.
// Every value must be there and nothing may follow: a count that disagrees with the values is an
// error at the line where they stop agreeing.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

#include "mesh/mesh_text.h"
#include "solver/photometry/photometric_text.h"

namespace lambert {
namespace {

using namespace photometry_io;

constexpr double kFootInMetres = 0.3048;

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::toupper(static_cast<unsigned char>(x)) == std::toupper(static_cast<unsigned char>(y));
         });
}

// The lines up to TILT=: the version, the keywords, and where the numbers begin.
struct Header {
  int year = 1986;
  std::string version;
  std::map<std::string, std::string> keywords;  // first occurrence of each, [MORE] lines appended
  std::string tilt;                             // what follows "TILT="
  std::size_t tilt_line = 0;
  std::size_t data_offset = 0;                  // byte after the TILT line
};

// The version a first line names, or 1986 for a file without one (its first line is a label).
int version_of(std::string_view first, Header& h) {
  struct Known { std::string_view line; int year; std::string_view name; };
  static constexpr Known kKnown[] = {{"IESNA91", 1991, "LM-63-1991"},
                                     {"IESNA:LM-63-1991", 1991, "LM-63-1991"},
                                     {"IESNA:LM-63-1995", 1995, "LM-63-1995"},
                                     {"IESNA:LM-63-2002", 2002, "LM-63-2002"},
                                     {"IES:LM-63-2019", 2019, "LM-63-2019"}};
  for (const Known& k : kKnown)
    if (first == k.line) {
      h.version = k.name;
      return k.year;
    }
  if (first.substr(0, 3) == "IES")
    fail(1, "unknown version line '" + std::string(first.substr(0, 40)) +
                "' (expected IESNA91, IESNA:LM-63-1995, IESNA:LM-63-2002 or IES:LM-63-2019)");
  h.version = "LM-63-1986";
  return 1986;
}

// A keyword line "[KEYWORD] text": the keyword's letters, digits and underscores (user keywords
// begin with one), at most 64 of them.
std::pair<std::string, std::string> keyword_line(std::string_view line, std::size_t number) {
  const std::size_t close = line.find(']');
  if (line.empty() || line.front() != '[' || close == std::string_view::npos)
    fail(number, "expected a keyword line '[KEYWORD] text' or the TILT= line, got '" +
                     std::string(line.substr(0, 40)) + "'");
  const std::string_view key = line.substr(1, close - 1);
  const bool valid = !key.empty() && key.size() <= 64 &&
                     std::all_of(key.begin(), key.end(), [](char c) {
                       return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
                     });
  if (!valid)
    fail(number, "bad keyword '[" + std::string(key.substr(0, 40)) +
                     "]' (keywords are 1 to 64 letters, digits or underscores)");
  return {std::string(key), std::string(trimmed(line.substr(close + 1)))};
}

Header read_header(std::string_view text, const PhotometricLimits& limits, std::vector<std::string>& notes) {
  Header h;
  mesh_io::TextLines lines(text);
  if (!lines.next()) fail(0, "the file is empty");
  std::string_view first = lines.line();
  if (first.substr(0, 3) == "\xEF\xBB\xBF") first.remove_prefix(3);  // a UTF-8 byte order mark
  h.year = version_of(trimmed(first), h);
  bool first_is_label = h.year == 1986;
  std::string last_key;
  for (std::size_t count = 0;; ++count) {
    if (!first_is_label && !lines.next()) fail(lines.number(), "the file ends before its TILT= line");
    const std::string_view line = trimmed(lines.line());
    if (line.substr(0, 5) == "TILT=") {
      h.tilt = std::string(trimmed(line.substr(5)));
      h.tilt_line = lines.number();
      h.data_offset = lines.offset();
      break;
    }
    if (count > limits.max_lines_before_data)
      fail(lines.number(), "more than " + std::to_string(limits.max_lines_before_data) + " lines before TILT=");
    first_is_label = false;
    if (h.year == 1986 || line.empty()) continue;  // 1986: free label lines
    auto [key, value] = keyword_line(line, lines.number());
    if (key == "MORE") {
      if (last_key.empty()) fail(lines.number(), "[MORE] continues no keyword");
      h.keywords[last_key] += "\n" + value;
      continue;
    }
    last_key = key;
    h.keywords.emplace(key, value);
  }
  // LM-63-2019 §5.2 requires four keywords; 1995 and 2002 require [TEST] and [MANUFAC].
  std::vector<std::string_view> required;
  if (h.year == 2019) required = {"TEST", "TESTLAB", "ISSUEDATE", "MANUFAC"};
  else if (h.year >= 1995) required = {"TEST", "MANUFAC"};
  for (std::string_view key : required)
    if (!h.keywords.count(std::string(key)))
      notes.push_back("the required keyword [" + std::string(key) + "] of " + h.version + " is missing");
  return h;
}

std::vector<double> read_values(WordCursor& words, std::size_t count, std::string_view what,
                                std::vector<std::size_t>* lines = nullptr) {
  std::vector<double> out;
  out.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    const std::string field = std::string(what) + " " + std::to_string(k + 1);
    const std::string_view word = next_word(words, field + " of " + std::to_string(count));
    out.push_back(real_field(word, words.line(), field));
    if (lines) lines->push_back(words.line());
  }
  return out;
}

TiltTable read_tilt(WordCursor& words, const PhotometricLimits& limits) {
  TiltTable t;
  t.lamp_to_luminaire_geometry = static_cast<int>(next_integer(words, "lamp-to-luminaire geometry", 1, 3));
  const long long n = next_integer(words, "number of tilt angles", 1, 1'000'000'000'000);
  check_declared(words.line(), "tilt angles", n, limits.max_tilt_angles, words.remaining_bytes(), 4);
  std::vector<std::size_t> lines;
  t.angles_deg = read_values(words, static_cast<std::size_t>(n), "tilt angle", &lines);
  check_ascending(t.angles_deg, lines, "tilt angle");
  for (std::size_t k = 0; k < t.angles_deg.size(); ++k)
    if (t.angles_deg[k] < 0 || t.angles_deg[k] > 180)
      fail(lines[k], "tilt angle " + std::to_string(k + 1) + ": " + number_text(t.angles_deg[k]) +
                         " is outside [0, 180]");
  lines.clear();
  t.factors = read_values(words, static_cast<std::size_t>(n), "tilt multiplying factor", &lines);
  for (std::size_t k = 0; k < t.factors.size(); ++k)
    if (t.factors[k] < 0)
      fail(lines[k], "tilt multiplying factor " + std::to_string(k + 1) + ": " + number_text(t.factors[k]) +
                         " is negative");
  return t;
}

}  // namespace

namespace {

// The numbers after the TILT line.
void read_photometry(WordCursor& words, const Header& h, const PhotometricLimits& limits, PhotometricData& d) {
  auto real = [&](std::string_view field) { return next_real(words, field); };
  auto integer = [&](std::string_view field, long long lo, long long hi) { return next_integer(words, field, lo, hi); };
  d.lamp_count = static_cast<int>(integer("number of lamps", 1, 1'000'000));
  const double lumens = real("lumens per lamp");
  const std::size_t lumens_line = words.line();
  d.absolute_photometry = lumens == -1;
  if (!d.absolute_photometry && !(lumens > 0))
    fail(lumens_line, "lumens per lamp: " + number_text(lumens) + " is neither positive nor -1 (absolute photometry)");
  if (!d.absolute_photometry) d.declared_lamp_flux_lm = d.lamp_count * lumens;
  d.multiplier = real("candela multiplier");
  if (!(d.multiplier > 0)) fail(words.line(), "candela multiplier: " + number_text(d.multiplier) + " is not positive");
  const long long nv = integer("number of vertical angles", 2, 1'000'000'000'000);
  check_declared(words.line(), "vertical angles", nv, limits.max_vertical_angles, words.remaining_bytes(), 2);
  const long long nh = integer("number of horizontal angles", 1, 1'000'000'000'000);
  check_declared(words.line(), "horizontal angles", nh, limits.max_horizontal_angles, words.remaining_bytes(), 2);
  check_declared(words.line(), "candela values (vertical × horizontal angles)", nv * nh, limits.max_values,
                 words.remaining_bytes(), 2);
  const long long type = integer("photometric type", 1, 3);
  d.type = type == 1 ? PhotometryType::kC : type == 2 ? PhotometryType::kB : PhotometryType::kA;
  const double unit_m = integer("units type", 1, 2) == 1 ? kFootInMetres : 1.0;
  const double width = real("width"), length = real("length"), height = real("height");
  const std::size_t dimension_line = words.line();
  d.ballast_factor = real("ballast factor");
  if (!(d.ballast_factor > 0)) fail(words.line(), "ballast factor: " + number_text(d.ballast_factor) + " is not positive");
  const double second = real(h.year >= 2019 ? "file generation type" : h.year >= 1995 ? "future use" : "ballast-lamp photometric factor");
  if (h.year < 1995 && !(second > 0)) fail(words.line(), "ballast-lamp photometric factor: " + number_text(second) + " is not positive");
  d.input_watts = real("input watts");
  if (d.input_watts < 0) fail(words.line(), "input watts: " + number_text(d.input_watts) + " is negative");
  d.opening = ies_opening(h.year, width * unit_m, length * unit_m, height * unit_m, dimension_line);

  std::vector<std::size_t> v_lines, h_lines;
  d.vertical_deg = read_values(words, static_cast<std::size_t>(nv), "vertical angle", &v_lines);
  check_ascending(d.vertical_deg, v_lines, "vertical angle");
  d.horizontal_deg = read_values(words, static_cast<std::size_t>(nh), "horizontal angle", &h_lines);
  check_ascending(d.horizontal_deg, h_lines, "horizontal angle");
  check_ies_ranges(d.type, d.vertical_deg, d.horizontal_deg, v_lines.front(), h_lines.front());
  const double scale = d.multiplier * d.ballast_factor * (h.year < 1995 ? second : 1.0);
  d.table_line = words.line() + 1;
  d.candela.reserve(static_cast<std::size_t>(nv * nh));
  for (long long i = 0; i < nh; ++i)
    for (long long j = 0; j < nv; ++j) {
      const std::string field = "candela value " + std::to_string(j + 1) + " of horizontal angle " +
                                number_text(d.horizontal_deg[static_cast<std::size_t>(i)]);
      const double value = next_real(words, field);
      if (value < 0) fail(words.line(), field + ": " + number_text(value) + " is negative");
      d.candela.push_back(value * scale);
    }
  if (auto extra = words.next())
    fail(words.line(), "'" + std::string(extra->substr(0, 40)) + "' follows the last of the " +
                           std::to_string(nv * nh) + " candela values the header declares");
}

}  // namespace

PhotometricParse parse_ies(std::string_view text, std::string_view name, const PhotometricLimits& limits) {
  PhotometricParse out;
  try {
    if (text.size() > limits.max_bytes)
      fail(0, "the file has " + std::to_string(text.size()) + " bytes; the limit is " + std::to_string(limits.max_bytes));
    if (text.find('\0') != std::string_view::npos) fail(0, "the file holds NUL bytes (not a text file)");
    PhotometricData d;
    d.format = PhotometricFormat::kIes;
    std::vector<std::string> notes;
    const Header h = read_header(text, limits, notes);
    d.version = h.version;
    if (auto it = h.keywords.find("LUMINAIRE"); it != h.keywords.end()) d.luminaire = it->second;
    if (auto it = h.keywords.find("MANUFAC"); it != h.keywords.end()) d.manufacturer = it->second;
    WordCursor words(text, h.data_offset, h.tilt_line + 1, true);
    if (equals_ignoring_case(h.tilt, "INCLUDE")) {
      d.tilt = read_tilt(words, limits);
    } else if (!equals_ignoring_case(h.tilt, "NONE")) {
      fail(h.tilt_line, "TILT=" + std::string(h.tilt.substr(0, 40)) +
                            ": tilt data in a separate file is not read (LM-63-2019 no longer allows it); "
                            "include it in the file with TILT=INCLUDE");
    }
    read_photometry(words, h, limits, d);
    for (const std::string& note : notes) d.warnings.push_back(std::string(name) + ": " + note);
    out.data = std::move(d);
  } catch (const ReadFailure& f) {
    out.error = located(name, f.line, f.message);
  }
  return out;
}

}  // namespace lambert
