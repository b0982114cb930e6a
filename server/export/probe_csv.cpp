#include "server/export/probe_csv.h"

#include <cstdio>

namespace lambert {
namespace {

// A field in double quotes, quotes doubled, where it holds a comma, a quote or a line break.
std::string field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? "\"\"" : std::string(1, c);
  return out + "\"";
}

// Round-trip precision: 17 significant digits give the double back.
std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

}  // namespace

std::string write_probe_csv(const ResultModel& model) {
  std::string out = "probe,u,v,x,y,z,illuminance_lx,quantity\r\n";
  for (const ResultProbe& p : model.probes)
    for (std::size_t q = 0; q < p.points.size(); ++q) {
      const std::size_t u = q % static_cast<std::size_t>(p.nu), v = q / static_cast<std::size_t>(p.nu);
      out += field(p.name) + "," + std::to_string(u) + "," + std::to_string(v) + "," + number(p.points[q].x) + "," +
             number(p.points[q].y) + "," + number(p.points[q].z) + "," + number(p.illuminance_lx[q]) + "," + field(p.quantity) + "\r\n";
    }
  return out;
}

}  // namespace lambert
