// The NOAA solar position and a clear-sky normal illuminance (see solar_position.h).
#include "solver/lights/solar_position.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include "solver/spectrum.h"

namespace lambert {
namespace {

constexpr double kDeg = kPi / 180;
double sin_deg(double x) { return std::sin(x * kDeg); }
double cos_deg(double x) { return std::cos(x * kDeg); }
double wrap360(double x) {
  const double r = std::fmod(x, 360.0);
  return r < 0 ? r + 360 : r;
}

bool leap_year(int y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }
int days_in_month(int y, int m) {
  static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return m == 2 && leap_year(y) ? 29 : kDays[m - 1];
}

// A cursor over the text that reads fixed-width digit fields and single characters.
struct Reader {
  std::string_view s;
  std::size_t i = 0;
  bool digits(int count, int& out) {
    out = 0;
    for (int k = 0; k < count; ++k, ++i) {
      if (i >= s.size() || !std::isdigit(static_cast<unsigned char>(s[i]))) return false;
      out = out * 10 + (s[i] - '0');
    }
    return true;
  }
  bool accept(char c) {
    if (i < s.size() && s[i] == c) return ++i, true;
    return false;
  }
  bool at_end() const { return i == s.size(); }
};

std::optional<Instant> fail(std::string* error, std::string message) {
  if (error) *error = std::move(message);
  return std::nullopt;
}

}  // namespace

double julian_day(int year, int month, int day, double day_fraction) {
  // Meeus (7.1), Gregorian calendar: January and February count as months 13 and 14 of the year before.
  if (month <= 2) year -= 1, month += 12;
  const int a = year / 100;
  const int b = 2 - a + a / 4;
  return std::floor(365.25 * (year + 4716)) + std::floor(30.6001 * (month + 1)) + day + b - 1524.5 + day_fraction;
}

std::optional<Instant> parse_iso8601(std::string_view text, std::string* error) {
  const std::string expected = "expected an ISO 8601 time with an offset, like \"2026-06-21T12:00:00+02:00\"";
  Reader r{text};
  int year, month, day, hour, minute, second = 0;
  if (!r.digits(4, year) || !r.accept('-') || !r.digits(2, month) || !r.accept('-') || !r.digits(2, day) ||
      !(r.accept('T') || r.accept('t') || r.accept(' ')) || !r.digits(2, hour) || !r.accept(':') || !r.digits(2, minute))
    return fail(error, expected);
  double fraction = 0;
  if (r.accept(':')) {
    if (!r.digits(2, second)) return fail(error, expected);
    if (r.accept('.') || r.accept(',')) {
      double scale = 0.1;
      bool any = false;
      while (!r.at_end() && std::isdigit(static_cast<unsigned char>(r.s[r.i]))) {
        fraction += scale * (r.s[r.i++] - '0');
        scale /= 10;
        any = true;
      }
      if (!any) return fail(error, expected);
    }
  }
  if (month < 1 || month > 12) return fail(error, "month " + std::to_string(month) + " is outside 1–12");
  if (day < 1 || day > days_in_month(year, month))
    return fail(error, "day " + std::to_string(day) + " does not exist in month " + std::to_string(month) + " of " +
                           std::to_string(year));
  if (hour > 23 || minute > 59 || second > 59) return fail(error, "the time of day is outside 00:00:00–23:59:59");
  int offset_minutes = 0;
  if (r.accept('Z') || r.accept('z')) {
  } else if (r.i < text.size() && (text[r.i] == '+' || text[r.i] == '-')) {
    const int sign = text[r.i++] == '-' ? -1 : 1;
    int oh, om = 0;
    if (!r.digits(2, oh)) return fail(error, expected);
    if (r.accept(':')) {
      if (!r.digits(2, om)) return fail(error, expected);
    } else if (!r.at_end() && !r.digits(2, om)) {
      return fail(error, expected);
    }
    if (oh > 14 || om > 59 || oh * 60 + om > 14 * 60) return fail(error, "the offset is outside ±14:00");
    offset_minutes = sign * (oh * 60 + om);
  } else {
    return fail(error, r.at_end() ? "the time has no offset from UTC (add \"Z\" or \"+hh:mm\")" : expected);
  }
  if (!r.at_end()) return fail(error, expected);
  Instant out;
  const double local_minutes = hour * 60 + minute + (second + fraction) / 60;
  out.julian_day_ut = julian_day(year, month, day, (local_minutes - offset_minutes) / 1440);
  out.year = year;
  out.day_of_year = static_cast<int>(julian_day(year, month, day) - julian_day(year, 1, 1)) + 1;
  return out;
}

SolarCoordinates solar_coordinates(double jd) {
  const double T = (jd - 2451545.0) / 36525;  // Julian centuries from J2000.0
  const double L0 = wrap360(280.46646 + T * (36000.76983 + T * 0.0003032));  // geometric mean longitude (25.2)
  const double M = 357.52911 + T * (35999.05029 - 0.0001537 * T);          // mean anomaly (25.3)
  const double e = 0.016708634 - T * (0.000042037 + 0.0000001267 * T);     // eccentricity (25.4)
  const double C = sin_deg(M) * (1.914602 - T * (0.004817 + 0.000014 * T)) + sin_deg(2 * M) * (0.019993 - 0.000101 * T) +
                   sin_deg(3 * M) * 0.000289;  // equation of the centre
  SolarCoordinates out;
  out.true_longitude_deg = L0 + C;
  const double v = M + C;  // true anomaly
  out.radius_au = 1.000001018 * (1 - e * e) / (1 + e * cos_deg(v));  // (25.5)
  const double omega = 125.04 - 1934.136 * T;
  out.apparent_longitude_deg = out.true_longitude_deg - 0.00569 - 0.00478 * sin_deg(omega);
  const double eps0 = 23 + (26 + (21.448 - T * (46.815 + T * (0.00059 - T * 0.001813))) / 60) / 60;  // (22.2)
  const double eps = eps0 + 0.00256 * cos_deg(omega);  // corrected for the apparent position (25.8)
  const double lambda = out.apparent_longitude_deg;
  out.right_ascension_deg = wrap360(std::atan2(cos_deg(eps) * sin_deg(lambda), cos_deg(lambda)) / kDeg);  // (25.6)
  out.declination_deg = std::asin(sin_deg(eps) * sin_deg(lambda)) / kDeg;                               // (25.7)
  // NOAA's equation of time (Smart's series in y = tan²(ε/2), L0, e and M), in minutes of time.
  const double y = std::pow(std::tan(eps * kDeg / 2), 2);
  const double E = y * sin_deg(2 * L0) - 2 * e * sin_deg(M) + 4 * e * y * sin_deg(M) * cos_deg(2 * L0) -
                   0.5 * y * y * sin_deg(4 * L0) - 1.25 * e * e * sin_deg(2 * M);
  out.equation_of_time_min = 4 * E / kDeg;
  return out;
}

double atmospheric_refraction_deg(double e) {
  // NOAA Solar Calculator: arcseconds, by elevation band.
  double arcsec = 0;
  if (e > 85) {
    arcsec = 0;
  } else if (e > 5) {
    const double t = std::tan(e * kDeg);
    arcsec = 58.1 / t - 0.07 / (t * t * t) + 0.000086 / std::pow(t, 5);
  } else if (e > -0.575) {
    arcsec = 1735 + e * (-518.2 + e * (103.4 + e * (-12.79 + e * 0.711)));
  } else {
    arcsec = -20.772 / std::tan(e * kDeg);
  }
  return arcsec / 3600;
}

SolarPosition solar_position(double jd, double latitude_deg, double longitude_deg) {
  SolarPosition out;
  out.coordinates = solar_coordinates(jd);
  const double delta = out.coordinates.declination_deg;
  // True solar time [min] from universal time: UT + equation of time + 4 min per degree east.
  const double ut_minutes = (jd + 0.5 - std::floor(jd + 0.5)) * 1440;
  const double true_solar = std::fmod(ut_minutes + out.coordinates.equation_of_time_min + 4 * longitude_deg, 1440.0);
  double H = (true_solar < 0 ? true_solar + 1440 : true_solar) / 4 - 180;
  out.hour_angle_deg = H;
  const double phi = latitude_deg;
  const double cos_zenith = std::clamp(sin_deg(phi) * sin_deg(delta) + cos_deg(phi) * cos_deg(delta) * cos_deg(H), -1.0, 1.0);
  const double geometric_elevation = 90 - std::acos(cos_zenith) / kDeg;
  out.elevation_deg = geometric_elevation + atmospheric_refraction_deg(geometric_elevation);
  out.zenith_deg = 90 - out.elevation_deg;
  // Meeus (13.5): the azimuth from the south, westward; +180° from the north, clockwise.
  const double from_south = std::atan2(sin_deg(H), cos_deg(H) * sin_deg(phi) - std::tan(delta * kDeg) * cos_deg(phi));
  out.azimuth_deg = wrap360(from_south / kDeg + 180);
  return out;
}

Vector3 direction_to_sun(const SolarPosition& sun, const Vector3& up, const Vector3& north) {
  const Vector3 east = cross(north, up);
  const double horizontal = cos_deg(sun.elevation_deg);
  return normalize(north * (horizontal * cos_deg(sun.azimuth_deg)) + east * (horizontal * sin_deg(sun.azimuth_deg)) +
                   up * sin_deg(sun.elevation_deg));
}

double relative_air_mass(double zenith_deg) {
  return 1 / (cos_deg(zenith_deg) + 0.50572 * std::pow(96.07995 - zenith_deg, -1.6364));
}

double clear_sky_normal_illuminance_lx(const SolarPosition& sun, int day_of_year) {
  if (!(sun.elevation_deg > 0)) return 0;
  constexpr double kSolarIlluminanceConstant = 128000;  // lx
  constexpr double kClearSkyExtinction = 0.21;
  const double extraterrestrial = kSolarIlluminanceConstant * (1 + 0.033412 * std::cos(2 * kPi * (day_of_year - 3) / 365));
  return extraterrestrial * std::exp(-kClearSkyExtinction * relative_air_mass(sun.zenith_deg));
}

}  // namespace lambert
