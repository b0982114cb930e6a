// The sun's position: the NOAA Solar Calculator's algorithm (NOAA Global Monitoring Laboratory,
// after J. Meeus, Astronomical Algorithms, 2nd ed. 1998, ch. 25 "Solar coordinates", low accuracy:
// about 0.01° in the sun's coordinates for the years 1800–2100), with NOAA's equation of time and
// its atmospheric refraction correction for a standard atmosphere. Universal time is used for
// dynamical time (ΔT ≈ 69 s moves the sun by 0.0008°).
//
// And a clear-sky direct normal illuminance, for a sun whose illuminance is not given:
//   E_n = E_sc (1 + 0.033412 cos(2π (n − 3)/365)) exp(−c m),
// E_sc = 128 000 lx the solar illuminance constant, n the day of the year (the orbit factor peaks at
// perihelion, about January 3), c = 0.21 the atmospheric extinction coefficient of a clear sky
// (IES Lighting Handbook), m the relative optical air mass of Kasten & Young (1989),
//   m = 1 / (cos Z + 0.50572 (96.07995 − Z)^−1.6364),   Z in degrees.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "mesh/geometry.h"

namespace lambert {

// An instant read from ISO 8601 "YYYY-MM-DDThh:mm[:ss[.fff]]" with an offset ("Z", "±hh:mm",
// "±hhmm" or "±hh"); the offset is required (a local time alone is ambiguous).
struct Instant {
  double julian_day_ut = 0;  // Julian day of the instant in universal time
  int year = 0, day_of_year = 0;
};
// The instant, or nullopt with the reason in *error.
std::optional<Instant> parse_iso8601(std::string_view text, std::string* error);
// Julian day of a Gregorian calendar date at 0 h UT plus `day_fraction` (Meeus ch. 7).
double julian_day(int year, int month, int day, double day_fraction = 0);

// The sun's geocentric apparent coordinates at a Julian day (Meeus ch. 25, as NOAA computes them).
struct SolarCoordinates {
  double true_longitude_deg = 0;      // ☉, of the mean equinox of the date
  double apparent_longitude_deg = 0;  // λ, corrected for nutation and aberration
  double right_ascension_deg = 0;     // α, in [0, 360)
  double declination_deg = 0;         // δ
  double radius_au = 0;               // R
  double equation_of_time_min = 0;    // apparent minus mean solar time (NOAA's series)
};
SolarCoordinates solar_coordinates(double julian_day);

// The sun seen from a place: latitude north positive, longitude east positive.
struct SolarPosition {
  double elevation_deg = 0;   // above the horizon, corrected for refraction
  double zenith_deg = 0;      // 90° − elevation_deg
  double azimuth_deg = 0;     // clockwise from north, in [0, 360)
  double hour_angle_deg = 0;  // from the meridian, positive in the afternoon
  SolarCoordinates coordinates;
};
SolarPosition solar_position(double julian_day_ut, double latitude_deg, double longitude_deg);

// NOAA's refraction correction [deg] for an elevation [deg] without refraction.
double atmospheric_refraction_deg(double elevation_deg);

// The unit vector towards the sun in a scene whose `up` and `north` (horizontal) are given (both unit,
// perpendicular); east = north × up.
Vector3 direction_to_sun(const SolarPosition& sun, const Vector3& up, const Vector3& north);

// The clear-sky direct normal illuminance [lx] above; 0 for a sun at or below the horizon.
double clear_sky_normal_illuminance_lx(const SolarPosition& sun, int day_of_year);
// Kasten & Young's relative air mass at zenith angle Z [deg].
double relative_air_mass(double zenith_deg);

}  // namespace lambert
