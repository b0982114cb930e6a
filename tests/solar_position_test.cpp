// The NOAA solar position (solver/lights/solar_position.h) against published tables: Meeus's worked
// example 25.a (the algorithm's own source, low-accuracy solar coordinates), and the NREL SPA's
// published example (Reda & Andreas 2004, NREL/TP-560-34302, table A4.1: an independent, 0.0003°
// algorithm), which NOAA's documented accuracy (about 0.01°) must meet. Plus the ISO 8601 reader
// and the clear-sky normal illuminance's parts.
#include "solver/lights/solar_position.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "solver/spectrum.h"

namespace lambert {
namespace {

TEST(SolarPosition, JulianDayOfMeeusExamples) {
  // Meeus example 7.a: 1957 October 4.81 → JD 2436116.31; example 7.b: 333 January 27.5 is Julian
  // calendar (not handled); J2000.0 = 2000 January 1.5 → 2451545.0.
  EXPECT_NEAR(julian_day(1957, 10, 4, 0.81), 2436116.31, 1e-9);
  EXPECT_DOUBLE_EQ(julian_day(2000, 1, 1, 0.5), 2451545.0);
  // Meeus 7.a table: 1987 June 19.5 → 2446966.0; 1988 January 27.0 → 2447187.5; 1600 December 31.0 → 2305812.5.
  EXPECT_DOUBLE_EQ(julian_day(1987, 6, 19, 0.5), 2446966.0);
  EXPECT_DOUBLE_EQ(julian_day(1988, 1, 27), 2447187.5);
  EXPECT_DOUBLE_EQ(julian_day(1600, 12, 31), 2305812.5);
}

TEST(SolarPosition, MeeusExample25a) {
  // 1992 October 13.0 TD (JDE 2448908.5), Meeus ch. 25, example 25.a:
  // ☉ = 199.90988°, R = 0.99766 AU, λ = 199.90895°, α = 198.38083° (13h13m31.4s), δ = −7.78507°.
  const SolarCoordinates c = solar_coordinates(2448908.5);
  EXPECT_NEAR(c.true_longitude_deg, 199.90988, 1e-5);
  EXPECT_NEAR(c.radius_au, 0.99766, 1e-5);
  EXPECT_NEAR(c.apparent_longitude_deg, 199.90895, 1e-5);
  EXPECT_NEAR(c.right_ascension_deg, 198.38083, 5e-5);
  EXPECT_NEAR(c.declination_deg, -7.78507, 5e-5);
  // Meeus example 28.a (the same instant, by the VSOP87 ephemeris): E = +13 min 42.6 s. NOAA's series
  // in the low-accuracy coordinates reproduces it within 0.2 s (0.05 s here).
  EXPECT_NEAR(c.equation_of_time_min, 13 + 42.6 / 60, 0.2 / 60);
}

TEST(SolarPosition, NrelSpaPublishedExample) {
  // Reda & Andreas (2004), the SPA's test case: 2003-10-17 12:30:30 local time, UTC−7, at 39.742476° N,
  // 105.1786° W: Julian day 2452930.312847; topocentric zenith 50.11162°, azimuth 194.34024°
  // (from the north, eastward). The SPA's refraction is for 820 mbar and 11 °C and includes parallax;
  // NOAA's is for a standard atmosphere: 0.003° apart here, within NOAA's 0.01°.
  std::string error;
  const auto instant = parse_iso8601("2003-10-17T12:30:30-07:00", &error);
  ASSERT_TRUE(instant) << error;
  EXPECT_NEAR(instant->julian_day_ut, 2452930.312847, 1e-6);
  EXPECT_EQ(instant->day_of_year, 290);
  const SolarPosition sun = solar_position(instant->julian_day_ut, 39.742476, -105.1786);
  EXPECT_NEAR(sun.zenith_deg, 50.11162, 0.005);
  EXPECT_NEAR(sun.azimuth_deg, 194.34024, 0.005);
}

TEST(SolarPosition, NoaaSpreadsheetTable) {
  // NOAA Global Monitoring Laboratory's own spreadsheet of the algorithm, NOAA_Solar_Calculations_day
  // (its default inputs: 40° N, 105° W, time zone −7, 21 June 2010), rows at 06:00, 08:00, 09:00,
  // 12:00, 15:00, 18:00 and 19:30 local time: "Solar Elevation corrected for atm refraction (deg)" and
  // "Solar Azimuth Angle (deg cw from N)" as the sheet holds them (read from the copy kept in
  // github.com/pyenergyplus/pysunNOAA, resources/NOAA_Solar_Calculations_day.ods).
  struct Row {
    const char* time;
    double elevation_deg, azimuth_deg;
  };
  const Row rows[] = {{"2010-06-21T06:00-07:00", 14.5538438427532, 71.3721272242721},
                      {"2010-06-21T08:00-07:00", 37.0589536901355, 89.0079648832438},
                      {"2010-06-21T09:00-07:00", 48.4962923894066, 99.4675295274194},
                      {"2010-06-21T12:00-07:00", 73.4384793439627, 178.533230037881},
                      {"2010-06-21T15:00-07:00", 49.1836829941271, 259.809563932718},
                      {"2010-06-21T18:00-07:00", 15.2132018370298, 288.099272917031},
                      {"2010-06-21T19:30-07:00", 0.0989819972923182, 301.72829080667}};
  for (const Row& row : rows) {
    std::string error;
    const auto instant = parse_iso8601(row.time, &error);
    ASSERT_TRUE(instant) << error;
    const SolarPosition sun = solar_position(instant->julian_day_ut, 40, -105);
    EXPECT_NEAR(sun.elevation_deg, row.elevation_deg, 1e-6) << row.time;
    EXPECT_NEAR(sun.azimuth_deg, row.azimuth_deg, 1e-6) << row.time;
  }
}

TEST(SolarPosition, DirectionInTheScene) {
  // The sun's direction from its elevation γ and azimuth A: north cos γ cos A + east cos γ sin A + up sin γ,
  // with east = north × up. A sun due south at 30° in a scene with up = z, north = y, east = x.
  SolarPosition sun;
  sun.elevation_deg = 30, sun.azimuth_deg = 180;
  const Vector3 d = direction_to_sun(sun, {0, 0, 1}, {0, 1, 0});
  EXPECT_NEAR(d.x, 0, 1e-15);
  EXPECT_NEAR(d.y, -std::cos(kPi / 6), 1e-15);
  EXPECT_NEAR(d.z, 0.5, 1e-15);
  sun.azimuth_deg = 90;  // due east: +x
  EXPECT_NEAR(direction_to_sun(sun, {0, 0, 1}, {0, 1, 0}).x, std::cos(kPi / 6), 1e-15);
}

TEST(SolarPosition, NoonStandsOnTheMeridian) {
  // At true solar noon the hour angle is 0 and the sun stands due south (north of the tropic):
  // local mean noon at 0° longitude, corrected by the equation of time.
  const double jd0 = julian_day(2026, 6, 21);
  const double eot = solar_coordinates(jd0 + 0.5).equation_of_time_min;
  const SolarPosition noon = solar_position(jd0 + (720 - eot) / 1440, 52.0, 0.0);
  EXPECT_NEAR(noon.hour_angle_deg, 0, 1e-3);
  EXPECT_NEAR(noon.azimuth_deg, 180, 2e-3);
  // Elevation at noon = 90° − φ + δ (+ refraction).
  const double delta = noon.coordinates.declination_deg;
  EXPECT_NEAR(noon.elevation_deg, 90 - 52 + delta + atmospheric_refraction_deg(90 - 52 + delta), 1e-6);
  EXPECT_NEAR(delta, 23.44, 0.01);  // the June solstice
}

TEST(SolarPosition, Iso8601Reader) {
  std::string error;
  const auto a = parse_iso8601("2026-06-21T12:00:00+02:00", &error);
  const auto b = parse_iso8601("2026-06-21T10:00:00Z", &error);
  const auto c = parse_iso8601("2026-06-21T05:30-0430", &error);
  const auto d = parse_iso8601("2026-06-21T10:00:00.000+00", &error);
  ASSERT_TRUE(a && b && c && d) << error;
  EXPECT_DOUBLE_EQ(a->julian_day_ut, b->julian_day_ut);
  EXPECT_NEAR(c->julian_day_ut, b->julian_day_ut, 1e-9);
  EXPECT_DOUBLE_EQ(d->julian_day_ut, b->julian_day_ut);
  EXPECT_EQ(a->day_of_year, 172);
  EXPECT_EQ(parse_iso8601("2024-12-31T00:00:00Z", &error)->day_of_year, 366);
  for (const char* bad : {"2026-06-21T12:00:00", "2026-02-29T12:00:00Z", "2026-13-01T00:00Z", "2026-06-21T24:00Z",
                          "2026-06-21 12:00:00+15:00", "21.06.2026 12:00", "2026-06-21T12:00:00+02:00 extra"}) {
    error.clear();
    EXPECT_FALSE(parse_iso8601(bad, &error)) << bad;
    EXPECT_FALSE(error.empty()) << bad;
  }
  parse_iso8601("2026-06-21T12:00:00", &error);
  EXPECT_NE(error.find("offset"), std::string::npos) << error;
}

TEST(SolarPosition, ClearSkyNormalIlluminance) {
  // Kasten & Young (1989): m = 1/(cos Z + 0.50572 (96.07995 − Z)^−1.6364): 0.99971 at the zenith,
  // 1.9943 at 60° (sec Z = 2 less the curvature), 37.9 at the horizon (their table).
  EXPECT_NEAR(relative_air_mass(0), 1 / (1 + 0.50572 * std::pow(96.07995, -1.6364)), 1e-15);
  EXPECT_NEAR(relative_air_mass(0), 0.99971, 1e-5);
  EXPECT_NEAR(relative_air_mass(60), 1.9943, 2e-4);
  EXPECT_NEAR(relative_air_mass(90), 37.92, 0.05);
  // E_n = 128 000 (1 + 0.033412 cos(2π (n − 3)/365)) exp(−0.21 m): at perihelion with the sun at the
  // zenith, 128 000 × 1.033412 × exp(−0.21 × 0.99971).
  SolarPosition zenith;
  zenith.elevation_deg = 90, zenith.zenith_deg = 0;
  EXPECT_NEAR(clear_sky_normal_illuminance_lx(zenith, 3), 128000 * 1.033412 * std::exp(-0.21 * relative_air_mass(0)),
              1e-9);
  SolarPosition below;
  below.elevation_deg = -1, below.zenith_deg = 91;
  EXPECT_EQ(clear_sky_normal_illuminance_lx(below, 3), 0);
}

}  // namespace
}  // namespace lambert
