// Writes IES LM-63 and EULUMDAT text from a function of the file's angles, for the tests: the
// distributions the tests check against closed forms are written here, not read from the tree.
// The direction of each photometry type's angles (docs/SPEC.md, "luminaire") is written out here
// again, independently of solver/photometry/distribution.cpp, as a test's answer must be.
#pragma once

#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/geometry.h"

namespace lambert::test {

inline constexpr double kDeg = 3.14159265358979323846 / 180;

inline std::vector<double> steps(double from, double to, double step) {
  std::vector<double> out;
  const int n = static_cast<int>(std::lround((to - from) / step));
  for (int k = 0; k <= n; ++k) out.push_back(from + (to - from) * k / n);
  return out;
}

// The luminaire-frame direction of a file's angles (x = C0, y = C90, z = up), per SPEC.
inline Vector3 type_c_direction(double c_deg, double gamma_deg) {
  const double c = c_deg * kDeg, g = gamma_deg * kDeg;
  return {std::sin(g) * std::cos(c), std::sin(g) * std::sin(c), -std::cos(g)};
}
inline Vector3 type_b_direction(double h_deg, double v_deg) {
  const double h = h_deg * kDeg, v = v_deg * kDeg;
  return {std::cos(h) * std::sin(v), -std::sin(h), -std::cos(h) * std::cos(v)};
}
inline Vector3 type_a_direction(double h_deg, double v_deg) {
  const double h = h_deg * kDeg, v = v_deg * kDeg;
  return {std::cos(v) * std::cos(h), -std::cos(v) * std::sin(h), std::sin(v)};
}

struct IesSpec {
  std::string version_line = "IESNA:LM-63-2002";
  std::vector<std::string> keywords = {"[TEST] lambert test", "[MANUFAC] lambert"};
  std::string tilt = "TILT=NONE";
  int type = 1;  // 1 C, 2 B, 3 A
  std::vector<double> vertical, horizontal;
  std::function<double(double horizontal, double vertical)> candela;
  int lamps = 1;
  double lumens_per_lamp = -1, multiplier = 1, ballast = 1, second = 1, watts = 10;
  int units = 2;
  double width = 0, length = 0, height = 0;
};

inline std::string ies_text(const IesSpec& s) {
  std::ostringstream o;
  o.precision(17);
  if (!s.version_line.empty()) o << s.version_line << "\r\n";
  for (const std::string& k : s.keywords) o << k << "\r\n";
  o << s.tilt << "\r\n";
  o << s.lamps << ' ' << s.lumens_per_lamp << ' ' << s.multiplier << ' ' << s.vertical.size() << ' '
    << s.horizontal.size() << ' ' << s.type << ' ' << s.units << ' ' << s.width << ' ' << s.length << ' ' << s.height
    << "\r\n";
  o << s.ballast << ' ' << s.second << ' ' << s.watts << "\r\n";
  for (double v : s.vertical) o << v << ' ';
  o << "\r\n";
  for (double h : s.horizontal) o << h << ' ';
  o << "\r\n";
  for (double h : s.horizontal) {
    for (double v : s.vertical) o << s.candela(h, v) << ' ';
    o << "\r\n";
  }
  return o.str();
}

struct LdtSpec {
  int isym = 0;
  int mc = 24;                     // C-planes in 360°
  std::vector<double> gamma = steps(0, 180, 5);
  std::function<double(double c, double gamma)> cd_per_klm;
  double lamp_flux = 1000, lorl = 100, conversion = 1, watts = 10;
  int lamps = 1;                   // negative: absolute photometry
  double area_length_mm = 0, area_width_mm = 0;
  double heights_mm[4] = {0, 0, 0, 0};
};

// The planes an LDT stores for its Isym (the reader's rule, written again here).
inline std::vector<double> ldt_stored_planes(const LdtSpec& s) {
  const double dc = 360.0 / s.mc;
  std::vector<double> out;
  for (int k = 0; k < s.mc; ++k) {
    const double c = k * dc;
    const bool keep = s.isym == 0 || (s.isym == 1 && k == 0) || (s.isym == 2 && c <= 180) ||
                      (s.isym == 3 && c >= 90 && c <= 270) || (s.isym == 4 && c <= 90);
    if (keep) out.push_back(c);
  }
  return out;
}

inline std::string ldt_text(const LdtSpec& s) {
  std::ostringstream o;
  o.precision(17);
  const double dc = 360.0 / s.mc;
  o << "Lambert test\r\n" << (s.isym == 1 ? 1 : 3) << "\r\n" << s.isym << "\r\n" << s.mc << "\r\n" << dc << "\r\n";
  o << s.gamma.size() << "\r\n" << 0 << "\r\n";
  o << "report\r\nluminaire\r\nnumber\r\nfile\r\ndate\r\n";
  o << 100 << "\r\n" << 100 << "\r\n" << 50 << "\r\n" << s.area_length_mm << "\r\n" << s.area_width_mm << "\r\n";
  for (double h : s.heights_mm) o << h << "\r\n";
  o << 100 << "\r\n" << s.lorl << "\r\n" << s.conversion << "\r\n" << 0 << "\r\n";
  o << 1 << "\r\n" << s.lamps << "\r\nLED\r\n" << s.lamp_flux << "\r\n3000 K\r\n90\r\n" << s.watts << "\r\n";
  for (int k = 0; k < 10; ++k) o << 0.5 << "\r\n";
  for (int k = 0; k < s.mc; ++k) o << k * dc << "\r\n";
  for (double g : s.gamma) o << g << "\r\n";
  for (double c : ldt_stored_planes(s))
    for (double g : s.gamma) o << s.cd_per_klm(c, g) << "\r\n";
  return o.str();
}

}  // namespace lambert::test
