#include "server/viewfactors/formats.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <map>

namespace lambert {
namespace {

// Text that reads back to the same double.
std::string exact(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

// Ten significant digits (the factors' accuracy is about 1e-9 at best), for readers of floats: View3D's
// and EnergyPlus's. A factor 1 that rounding left at 1 + 2e-16 is written as 1, not above
// EnergyPlus's maximum of 1.
std::string ten_digits(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", v);
  return text;
}

// EnergyPlus reads an object's fields up to ',' or ';', a comment from '!', and names of at most
// 100 characters, compared without case.
void check_energyplus_name(const std::string& name, const std::string& what) {
  if (name.empty() || name.size() > 100 || name.find_first_of(",;!\n\r") != std::string::npos)
    throw std::invalid_argument(what + " \"" + name + "\" cannot be an EnergyPlus name (1 to 100 characters, "
                                "without ',', ';' or '!')");
}

}  // namespace

std::string view_factors_csv(const ViewFactorMatrix& m) {
  std::string out = "i,j,F_ij\r\n";
  const std::size_t S = m.size();
  for (std::size_t I = 0; I < S; ++I)
    for (std::size_t J = 0; J < S; ++J)
      if (m.at(I, J) != 0) out += std::to_string(I) + "," + std::to_string(J) + "," + exact(m.at(I, J)) + "\r\n";
  return out;
}

std::string view_factors_view3d(const ViewFactorMatrix& m, const std::vector<double>& factors,
                                const std::vector<std::optional<double>>& emissivity, const View3dHeader& header) {
  const std::size_t S = m.size();
  char line[64];
  std::snprintf(line, sizeof line, "%s %s 0 %d %d %zu", header.program.c_str(), header.version.c_str(),
                header.enclosure ? 1 : 0, header.with_emittances ? 1 : 0, S);
  std::string out = line;
  out.resize(std::max<std::size_t>(out.size(), 30), ' ');  // View3D pads its header to 30 characters
  out += "\n";
  auto row = [&](auto value) {
    for (std::size_t k = 0; k < S; ++k) {
      if (k) out += ' ';
      out += value(k);
    }
    out += "\n";
  };
  row([&](std::size_t I) { return ten_digits(m.area_m2[I]); });
  for (std::size_t I = 0; I < S; ++I) row([&](std::size_t J) { return ten_digits(factors[I * S + J]); });
  row([&](std::size_t I) { return ten_digits(I < emissivity.size() && emissivity[I] ? *emissivity[I] : 1.0); });
  return out;
}

std::string view_factors_idf(const ViewFactorMatrix& m, const std::string& zone, const std::string& comment) {
  check_energyplus_name(zone, "the zone name");
  std::map<std::string, std::string> seen;  // lower case -> name
  for (const std::string& name : m.names) {
    check_energyplus_name(name, "surface name");
    std::string key = name;
    std::transform(key.begin(), key.end(), key.begin(), [](unsigned char c) { return std::tolower(c); });
    if (const auto [it, added] = seen.emplace(key, name); !added)
      throw std::invalid_argument("surface names \"" + it->second + "\" and \"" + name +
                                  "\" are one EnergyPlus name (names are compared without case)");
  }
  std::string out = "! " + comment + "\n";
  out += "ZoneProperty:UserViewFactors:BySurfaceName,\n";
  out += "  " + zone + ",  !- Zone or ZoneList or Space or SpaceList Name\n";
  const std::size_t S = m.size();
  std::size_t n = 0;
  for (std::size_t I = 0; I < S; ++I)
    for (std::size_t J = 0; J < S; ++J) {
      ++n;
      const bool last = I + 1 == S && J + 1 == S;
      out += "  " + m.names[I] + ",  !- From Surface " + std::to_string(n) + "\n";
      out += "  " + m.names[J] + ",  !- To Surface " + std::to_string(n) + "\n";
      out += "  " + ten_digits(m.at(I, J)) + (last ? ";" : ",") + "  !- View Factor " + std::to_string(n) + "\n";
    }
  return out;
}

}  // namespace lambert
