// CIE 171:2006, "Test cases to assess the accuracy of lighting computer programs", the daylight cases
// whose reference is computed, not measured: test case 5.9 (the sky component through an unglazed roof
// opening) and 5.11 (sky and externally reflected components through an unglazed façade opening),
// run through the whole solve (scene JSON → result JSON) for the 15 ISO 15469 general skies and the
// traditional CIE overcast sky ("type 16").
//
// The set-up (CIE 171 §5.9 and §5.11): a 4 × 4 × 3 m room whose surfaces reflect nothing, the sun at
// 60° elevation in the south (for the skies that depend on it; its direct light is not counted), the
// results in per cent of the sky's unobstructed horizontal illuminance. 5.9: a 1 × 1 m opening in the
// middle of the ceiling, or the whole ceiling open (4 × 4); points A–F on the wall that faces the sun,
// 0.25 to 2.75 m high, and G–N across the floor from that wall. 5.11: a 2 × 1 m opening with its sill
// 1 m high in the middle of the south wall, or the whole wall open (4 × 3), a ground of reflectance 0.3;
// points A–F on the wall facing the opening, G–N on the floor and G'–N' on the ceiling from the far
// wall to the opening. The reference values are those of CIE 171's Appendix B (Tables B.1–B.4 and
// B.9–B.14), as transcribed in github.com/jjathompson4/CyclesCIEtest
// (engine/cie171/test_cases_daylight.py), which also records the report's errata; here x points east,
// y north, z up.
//
// Where a closed form exists (sky type 5, whose luminance is uniform, everywhere; the overcast sky at
// the floor under the roof opening; the ground alone seen from the ceiling), the result is held to it
// to 1e-6 per cent; everywhere else to the printed tables (tolerances at the tests). CIE 171 itself is
// not public: the tables were checked against that transcription only, and the solve, agreeing with
// the small openings' tables to their rounding under all 16 skies, is their second witness.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "solver/lights/sky_luminance.h"
#include "tests/daylight_scenes.h"
#include "tests/test_geometry.h"

namespace lambert {
namespace {

using namespace test::daylight;

// ---- CIE 171:2006 Appendix B, per sky type 1–16 ----------------------------------------------------
// 5.9, 1 × 1 m: Table B.1 (A–F) and B.2 (G–N).
constexpr std::array<std::array<double, 14>, 16> kRoof1x1 = {{
    {0.46, 1.64, 2.34, 2.26, 1.88, 1.47, 2.33, 3.11, 3.84, 4.29, 4.29, 3.84, 3.11, 2.33},  // 1
    {0.40, 1.72, 2.86, 3.15, 2.90, 2.44, 4.00, 5.00, 5.47, 5.37, 4.73, 3.76, 2.76, 1.90},  // 2
    {0.79, 2.05, 2.46, 2.22, 1.78, 1.36, 2.13, 2.80, 3.42, 3.81, 3.81, 3.42, 2.80, 2.13},  // 3
    {0.71, 2.17, 3.06, 3.15, 2.79, 2.30, 3.72, 4.58, 4.97, 4.85, 4.27, 3.42, 2.53, 1.77},  // 4
    {1.04, 2.39, 2.59, 2.20, 1.70, 1.27, 1.95, 2.52, 3.04, 3.37, 3.37, 3.04, 2.52, 1.95},  // 5
    {0.94, 2.58, 3.27, 3.16, 2.71, 2.19, 3.47, 4.20, 4.49, 4.36, 3.84, 3.09, 2.31, 1.65},  // 6
    {0.82, 2.52, 3.61, 3.91, 3.69, 3.19, 5.21, 5.96, 5.70, 4.93, 3.92, 2.90, 2.04, 1.39},  // 7
    {0.72, 2.43, 3.86, 4.56, 4.60, 4.18, 6.94, 7.65, 6.78, 5.38, 3.93, 2.71, 1.80, 1.17},  // 8
    {1.64, 3.53, 3.67, 3.14, 2.49, 1.91, 2.88, 3.34, 3.45, 3.29, 2.89, 2.37, 1.83, 1.37},  // 9
    {1.46, 3.52, 4.13, 3.96, 3.45, 2.84, 4.42, 4.85, 4.49, 3.80, 3.02, 2.27, 1.65, 1.18},  // 10
    {1.30, 3.46, 4.49, 4.69, 4.39, 3.79, 6.01, 6.36, 5.45, 4.23, 3.09, 2.16, 1.48, 1.01},  // 11
    {1.74, 3.76, 4.55, 4.61, 4.24, 3.63, 5.72, 6.01, 5.12, 3.97, 2.90, 2.03, 1.40, 0.96},  // 12
    {1.61, 3.76, 4.87, 5.16, 4.89, 4.26, 6.76, 7.01, 5.80, 4.30, 2.98, 1.99, 1.30, 0.86},  // 13
    {2.22, 4.01, 4.88, 5.05, 4.72, 4.08, 6.43, 6.64, 5.47, 4.05, 2.81, 1.87, 1.23, 0.82},  // 14
    {2.14, 4.16, 5.23, 5.47, 5.11, 4.41, 6.94, 7.19, 5.93, 4.36, 2.96, 1.90, 1.20, 0.76},  // 15
    {0.56, 1.78, 2.32, 2.20, 1.82, 1.43, 2.29, 3.07, 3.82, 4.29, 4.29, 3.82, 3.07, 2.29},  // 16
}};
// 5.9, 4 × 4 m: Tables B.3 and B.4.
constexpr std::array<std::array<double, 14>, 16> kRoof4x4 = {{
    {37.84, 31.72, 26.85, 22.10, 17.89, 14.38, 31.87, 37.30, 41.27, 43.35, 43.35, 41.27, 37.30, 31.87},  // 1
    {42.03, 37.03, 32.75, 28.13, 23.70, 19.79, 42.01, 46.99, 49.85, 50.08, 47.76, 42.89, 36.40, 29.02},  // 2
    {42.77, 34.03, 27.43, 21.81, 17.23, 13.61, 29.16, 33.92, 37.40, 39.22, 39.22, 37.40, 33.92, 29.16},  // 3
    {46.85, 39.59, 33.65, 28.08, 23.16, 19.04, 39.19, 43.59, 46.07, 46.17, 43.97, 39.50, 33.60, 26.94},  // 4
    {46.74, 36.05, 28.05, 21.67, 16.73, 12.98, 26.80, 30.95, 33.99, 35.58, 35.58, 33.99, 30.95, 26.80},  // 5
    {50.91, 41.92, 34.58, 28.15, 22.76, 18.41, 36.63, 40.47, 42.59, 42.57, 40.48, 36.37, 31.03, 25.04},  // 6
    {51.83, 44.95, 38.55, 32.55, 27.23, 22.77, 44.08, 47.33, 48.53, 47.09, 43.13, 36.83, 29.80, 22.81},  // 7
    {52.27, 47.46, 41.91, 36.33, 31.13, 26.65, 50.65, 53.33, 53.73, 51.05, 45.38, 37.05, 28.56, 20.78},  // 8
    {61.28, 47.22, 36.33, 27.92, 21.55, 16.78, 30.70, 33.35, 34.69, 34.41, 32.58, 29.29, 25.19, 20.69},  // 9
    {61.85, 50.36, 40.59, 32.56, 26.13, 21.10, 37.82, 39.98, 40.52, 38.95, 35.42, 30.18, 24.58, 19.14},  // 10
    {61.99, 53.01, 44.28, 36.68, 30.26, 25.08, 44.36, 46.04, 45.85, 43.10, 37.95, 30.84, 23.89, 17.68},  // 11
    {66.34, 54.33, 44.25, 36.10, 29.48, 24.25, 42.33, 43.82, 43.54, 40.85, 35.92, 29.17, 22.62, 16.79},  // 12
    {66.63, 56.51, 47.18, 39.24, 32.56, 27.15, 42.07, 48.25, 47.47, 43.96, 37.92, 29.91, 22.38, 15.95},  // 13
    {71.83, 57.51, 46.84, 38.44, 31.62, 26.20, 44.95, 45.99, 45.15, 41.74, 35.96, 28.34, 21.22, 15.16},  // 14
    {73.20, 60.07, 49.66, 41.13, 34.02, 28.29, 48.42, 49.33, 48.19, 44.25, 37.79, 29.37, 21.53, 14.91},  // 15
    {39.28, 32.32, 26.79, 21.78, 17.53, 14.05, 31.36, 36.76, 40.71, 42.76, 42.76, 40.71, 36.76, 31.36},  // 16
}};
// 5.11, 2 × 1 m: Table B.9 (A–F, sky and ground), B.10 (G–N), B.11 (G'–N', ground only).
constexpr std::array<std::array<double, 6>, 16> kFacadeWall2x1 = {{
    {0.95, 1.06, 1.25, 1.51, 1.70, 1.86},  // 1
    {0.95, 1.06, 1.18, 1.33, 1.55, 1.83},  // 2
    {0.95, 1.06, 1.56, 2.42, 2.75, 2.58},  // 3
    {0.95, 1.06, 1.45, 2.14, 2.53, 2.58},  // 4
    {0.95, 1.06, 1.79, 3.09, 3.54, 3.17},  // 5
    {0.95, 1.06, 1.65, 2.76, 3.32, 3.22},  // 6
    {0.95, 1.06, 1.53, 2.43, 2.96, 3.01},  // 7
    {0.95, 1.06, 1.42, 2.13, 2.64, 2.81},  // 8
    {0.95, 1.06, 2.27, 4.61, 5.52, 4.82},  // 9
    {0.95, 1.06, 2.08, 4.10, 5.03, 4.61},  // 10
    {0.95, 1.06, 1.91, 3.65, 4.56, 4.38},  // 11
    {0.95, 1.06, 2.39, 4.93, 5.80, 5.01},  // 12
    {0.95, 1.06, 2.23, 4.52, 5.43, 4.87},  // 13
    {0.95, 1.06, 3.34, 6.87, 7.12, 5.51},  // 14
    {0.95, 1.06, 3.17, 6.54, 6.96, 5.58},  // 15
    {0.95, 1.06, 1.28, 1.71, 2.06, 2.14},  // 16
}};
constexpr std::array<std::array<double, 8>, 16> kFacadeFloor2x1 = {{
    {0.87, 1.31, 2.02, 3.20, 5.07, 7.64, 9.33, 5.09},  // 1
    {0.92, 1.42, 2.30, 3.86, 6.58, 10.77, 13.66, 6.33},  // 2
    {1.08, 1.54, 2.26, 3.40, 5.11, 7.34, 8.61, 4.56},  // 3
    {1.16, 1.71, 2.62, 4.16, 6.73, 10.52, 12.82, 5.80},  // 4
    {1.27, 1.75, 2.49, 3.59, 5.19, 7.11, 7.99, 4.13},  // 5
    {1.37, 1.97, 2.92, 4.46, 6.91, 10.33, 12.07, 5.30},  // 6
    {1.34, 1.98, 3.04, 4.86, 8.04, 13.00, 15.85, 5.97},  // 7
    {1.30, 1.96, 3.10, 5.16, 8.96, 15.41, 19.39, 6.50},  // 8
    {1.87, 2.55, 3.55, 5.05, 7.19, 9.74, 10.30, 4.19},  // 9
    {1.87, 2.61, 3.77, 5.61, 8.50, 12.47, 13.77, 4.81},  // 10
    {1.84, 2.63, 3.91, 6.04, 9.62, 15.00, 17.13, 5.33},  // 11
    {2.00, 2.80, 4.06, 6.13, 9.54, 14.57, 16.35, 5.03},  // 12
    {2.00, 2.85, 4.21, 6.52, 10.43, 16.41, 18.67, 5.43},  // 13
    {2.14, 2.98, 4.32, 6.55, 10.29, 15.89, 17.82, 5.14},  // 14
    {2.22, 3.12, 4.57, 6.99, 11.08, 17.18, 19.25, 5.52},  // 15
    {0.95, 1.38, 2.07, 3.19, 4.97, 7.42, 9.11, 5.04},  // 16
}};
// 5.11, 4 × 3 m: Tables B.12, B.13 and B.14.
constexpr std::array<std::array<double, 6>, 16> kFacadeWall4x3 = {{
    {5.25, 6.11, 6.98, 7.99, 8.77, 9.35},  // 1
    {5.09, 5.78, 6.56, 7.52, 8.49, 9.35},  // 2
    {5.93, 7.75, 9.33, 11.09, 12.03, 12.60},  // 3
    {5.66, 7.23, 8.72, 10.43, 11.64, 12.58},  // 4
    {6.43, 8.96, 11.11, 13.47, 14.57, 15.17},  // 5
    {6.10, 8.34, 10.42, 12.76, 14.21, 15.25},  // 6
    {5.82, 7.72, 9.56, 11.67, 13.19, 14.41},  // 7
    {5.59, 7.18, 8.81, 10.70, 12.23, 13.57},  // 8
    {7.42, 11.65, 15.25, 19.22, 21.12, 22.28},  // 9
    {7.00, 10.71, 14.02, 17.73, 19.81, 21.25},  // 10
    {6.62, 9.87, 12.91, 16.34, 18.51, 20.18},  // 11
    {7.63, 12.15, 15.80, 19.96, 22.13, 23.68},  // 12
    {7.27, 11.39, 14.85, 18.82, 21.13, 22.89},  // 13
    {9.65, 15.54, 19.50, 24.59, 26.56, 28.04},  // 14
    {9.25, 14.90, 18.88, 23.94, 26.17, 27.92},  // 15
    {5.29, 6.46, 7.67, 8.88, 9.73, 10.29},  // 16
}};
constexpr std::array<std::array<double, 8>, 16> kFacadeFloor4x3 = {{
    {4.27, 5.92, 8.33, 11.82, 16.84, 23.83, 33.05, 44.06},  // 1
    {4.70, 6.71, 9.75, 14.30, 21.00, 30.09, 41.22, 52.94},  // 2
    {5.09, 6.84, 9.33, 12.87, 17.86, 24.72, 33.68, 44.76},  // 3
    {5.62, 7.76, 10.91, 15.52, 22.17, 31.06, 41.86, 53.53},  // 4
    {5.79, 7.63, 10.20, 13.78, 18.76, 25.50, 34.24, 45.29},  // 5
    {6.43, 8.70, 11.96, 16.65, 23.25, 31.96, 42.44, 54.02},  // 6
    {6.49, 8.99, 12.70, 18.22, 26.22, 36.60, 48.26, 59.49},  // 7
    {6.47, 9.14, 13.23, 19.48, 28.80, 40.72, 53.40, 64.13},  // 8
    {8.36, 10.89, 14.38, 19.18, 25.67, 33.95, 43.73, 55.27},  // 9
    {8.52, 11.33, 15.32, 20.96, 28.76, 38.52, 49.29, 60.36},  // 10
    {8.58, 11.61, 16.02, 22.45, 31.52, 42.70, 54.36, 64.85},  // 11
    {9.26, 12.35, 16.79, 23.17, 32.10, 43.03, 54.44, 65.07},  // 12
    {9.38, 12.66, 17.43, 24.38, 34.19, 46.11, 58.17, 68.48},  // 13
    {10.48, 14.00, 19.08, 26.41, 36.64, 48.97, 61.35, 71.65},  // 14
    {10.48, 14.00, 19.08, 26.41, 36.64, 48.97, 61.35, 71.65},  // 15
    {4.50, 6.15, 8.53, 12.00, 16.97, 23.91, 33.08, 44.43},  // 16
}};
constexpr std::array<double, 8> kFacadeCeiling2x1 = {0.38, 0.53, 0.75, 1.08, 1.56, 2.14, 2.40, 1.24};
constexpr std::array<double, 8> kFacadeCeiling4x3 = {1.74, 2.29, 3.06, 4.14, 5.63, 7.65, 10.27, 13.59};

constexpr double kSunElevation = 60 * kPi / 180;

// The heights of A–F and the distances of G–N from the north wall (y = 4).
double wall_height(int k) { return 2.75 - 0.5 * k; }  // A = 0 … F = 5
double floor_y(int k) { return 3.75 - 0.5 * k; }      // G = 0 … N = 7

json cie_sky(int type, double ground_reflectance) {
  json light = sky(type, "horizontal_illuminance_lx", 10000);  // so that lx / 100 is the per cent of E_h
  light["ground_reflectance"] = ground_reflectance;
  if (type != kCieOvercastSkyType && cie_sky_depends_on_sun(type))
    light["sun_direction"] = {0, -std::cos(kSunElevation), std::sin(kSunElevation)};
  return light;
}

// The room [0,4]² × [0,3], black, without the faces (or parts) that the opening takes.
json roof_room(bool whole_ceiling) {
  json s = json::array({rectangle("floor", "black", {0, 0, 0}, {4, 0, 0}, {0, 4, 0}),
                        rectangle("south", "black", {0, 0, 0}, {0, 0, 3}, {4, 0, 0}),
                        rectangle("north", "black", {0, 4, 0}, {4, 0, 0}, {0, 0, 3}),
                        rectangle("west", "black", {0, 0, 0}, {0, 4, 0}, {0, 0, 3}),
                        rectangle("east", "black", {4, 0, 0}, {0, 0, 3}, {0, 4, 0})});
  if (!whole_ceiling)
    for (const json& r : {rectangle("ceiling south", "black", {0, 0, 3}, {0, 1.5, 0}, {4, 0, 0}),
                          rectangle("ceiling north", "black", {0, 2.5, 3}, {0, 1.5, 0}, {4, 0, 0}),
                          rectangle("ceiling west", "black", {0, 1.5, 3}, {0, 1, 0}, {1.5, 0, 0}),
                          rectangle("ceiling east", "black", {2.5, 1.5, 3}, {0, 1, 0}, {1.5, 0, 0})})
      s.push_back(r);
  return s;
}

json facade_room(bool whole_wall) {
  json s = json::array({rectangle("floor", "black", {0, 0, 0}, {4, 0, 0}, {0, 4, 0}),
                        rectangle("ceiling", "black", {0, 0, 3}, {0, 4, 0}, {4, 0, 0}),
                        rectangle("north", "black", {0, 4, 0}, {4, 0, 0}, {0, 0, 3}),
                        rectangle("west", "black", {0, 0, 0}, {0, 4, 0}, {0, 0, 3}),
                        rectangle("east", "black", {4, 0, 0}, {0, 0, 3}, {0, 4, 0})});
  if (!whole_wall)
    for (const json& r : {rectangle("south below", "black", {0, 0, 0}, {0, 0, 1}, {4, 0, 0}),
                          rectangle("south above", "black", {0, 0, 2}, {0, 0, 1}, {4, 0, 0}),
                          rectangle("south west", "black", {0, 0, 1}, {0, 0, 1}, {1, 0, 0}),
                          rectangle("south east", "black", {3, 0, 1}, {0, 0, 1}, {1, 0, 0})})
      s.push_back(r);
  return s;
}

// The points of a case: A–F on the north wall facing south, G–N on the floor and (façade) G'–N' on the
// ceiling facing down.
json cie_probes(bool ceiling) {
  json probes = json::array();
  for (int k = 0; k < 6; ++k) probes.push_back(probe(std::string(1, static_cast<char>('A' + k)), {2, 4, wall_height(k)}, {0, -1, 0}));
  for (int k = 0; k < 8; ++k) probes.push_back(probe(std::string(1, static_cast<char>('G' + k)), {2, floor_y(k), 0}, {0, 0, 1}));
  if (ceiling)
    for (int k = 0; k < 8; ++k) probes.push_back(probe(std::string(1, static_cast<char>('G' + k)) + "'", {2, floor_y(k), 3}, {0, 0, -1}));
  return probes;
}

// Per cent of E_h at every probe of the solved case.
std::vector<double> per_cent(const json& result) {
  std::vector<double> out;
  for (const json& p : result["probes"]) out.push_back(p["illuminance_lx"].get<double>() / 100);
  return out;
}

// ---- the exact answers --------------------------------------------------------------------------

// The opening: [x0, x1] × [y0, y1] at z = 3 (roof) or [x0, x1] × [z0, z1] at y = 0 (façade).
struct Opening {
  double x0, x1, a0, a1;
};
constexpr Opening kRoofOpening1x1{1.5, 2.5, 1.5, 2.5}, kRoofOpening4x4{0, 4, 0, 4};
constexpr Opening kFacadeOpening2x1{1, 3, 1, 2}, kFacadeOpening4x3{0, 4, 0, 3};

// Under the roof opening, per cent of E_h. Floor: uniform sky 100 F (B-3 corners); CIE overcast sky
// 100 (3/(7π)) (π F + 2 M), M the second moment of the opening (closed_forms.h). Wall (facing −y at
// y = 4): uniform sky 100 F, Howell V2 corners, the opening seen in the plane 3 − z above the point.
double roof_floor_uniform(const Opening& o, int k) {
  return 100 * test::point_under_rectangle(2, floor_y(k), 3, o.x0, o.x1, o.a0, o.a1);
}
double roof_floor_overcast(const Opening& o, int k) {
  const double F = test::point_under_rectangle(2, floor_y(k), 3, o.x0, o.x1, o.a0, o.a1);
  const double M = test::under_rectangle(test::second_moment_b3, 2, floor_y(k), 3, o.x0, o.x1, o.a0, o.a1);
  return 100 * 3 / (7 * kPi) * (kPi * F + 2 * M);
}
double roof_wall_uniform(const Opening& o, int k) {
  return 100 * test::perpendicular_rectangle(o.x0 - 2, o.x1 - 2, 4 - o.a1, 4 - o.a0, 3 - wall_height(k));
}

// Through the façade opening. Floor, uniform sky: 100 F (V2 corners, the window at distance y).
// Ceiling: only ground, luminance ρ_g E_h/π: 100 ρ_g F (V2, the window below the ceiling's plane).
// Wall (facing the window at distance 4): the window's part above the point's horizon is sky, below it
// ground: uniform sky 100 (F_above + ρ_g F_below), B-3 corners in the window's plane.
constexpr double kGround = 0.3;
double facade_floor_uniform(const Opening& o, int k) {
  return 100 * test::perpendicular_rectangle(o.x0 - 2, o.x1 - 2, o.a0, o.a1, floor_y(k));
}
double facade_ceiling(const Opening& o, int k) {
  return 100 * kGround * test::perpendicular_rectangle(o.x0 - 2, o.x1 - 2, 3 - o.a1, 3 - o.a0, floor_y(k));
}
double facade_wall_uniform(const Opening& o, int k) {
  const double z = wall_height(k), lo = o.a0 - z, hi = o.a1 - z;
  const double above = hi > 0 ? test::point_under_rectangle(0, 0, 4, o.x0 - 2, o.x1 - 2, std::max(lo, 0.0), hi) : 0;
  const double below = lo < 0 ? test::point_under_rectangle(0, 0, 4, o.x0 - 2, o.x1 - 2, lo, std::min(hi, 0.0)) : 0;
  return 100 * (above + kGround * below);
}

// ---- the cases ----------------------------------------------------------------------------------

// What one case's table says at probe q, NaN where it gives nothing to hold the result to.
using TableAt = std::function<double(int type, std::size_t q)>;
// The exact answer at probe q under sky `type`, NaN where there is none.
using ExactAt = std::function<double(int type, std::size_t q)>;

// Solves the case under all 16 skies. Every exact answer holds to 1e-6 per cent (the solve integrates
// the sky exactly at probes: what is left is the closed forms' own rounding); every table value to
// `abs` per cent plus `rel` of itself.
void run_case(const json& surfaces, bool ceiling, double ground, const TableAt& table, const ExactAt& exact,
              double abs, double rel) {
  int exact_checked = 0;
  for (int type = 1; type <= 16; ++type) {
    const std::vector<double> got =
        per_cent(solve_json(scene_with(surfaces, json::array({cie_sky(type, ground)}), cie_probes(ceiling))));
    for (std::size_t q = 0; q < got.size(); ++q) {
      const double want = exact(type, q), printed = table(type, q);
      if (!std::isnan(want)) {
        EXPECT_NEAR(got[q], want, 1e-6) << "sky type " << type << ", probe " << q;
        ++exact_checked;
      }
      if (!std::isnan(printed)) {
        EXPECT_NEAR(got[q], printed, abs + rel * printed) << "sky type " << type << ", probe " << q << " (table)";
      }
    }
  }
  EXPECT_GT(exact_checked, 0);
}

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

// 5.9, points A–F on the wall, then G–N on the floor.
TableAt roof_table(const std::array<std::array<double, 14>, 16>& t) {
  return [&t](int type, std::size_t q) { return t[type - 1][q]; };
}
ExactAt roof_exact(const Opening& o) {
  return [o](int type, std::size_t q) {
    const int k = static_cast<int>(q);
    if (type == 5) return q < 6 ? roof_wall_uniform(o, k) : roof_floor_uniform(o, k - 6);
    if (type == kCieOvercastSkyType && q >= 6) return roof_floor_overcast(o, k - 6);
    return kNone;
  };
}

// 5.11, points A–F on the wall, G–N on the floor, G'–N' on the ceiling.
TableAt facade_table(const std::array<std::array<double, 6>, 16>& wall, const std::array<std::array<double, 8>, 16>& floor,
                     const std::array<double, 8>& ceiling) {
  return [&](int type, std::size_t q) {
    return q < 6 ? wall[type - 1][q] : q < 14 ? floor[type - 1][q - 6] : ceiling[q - 14];
  };
}
ExactAt facade_exact(const Opening& o) {
  return [o](int type, std::size_t q) {
    const int k = static_cast<int>(q);
    if (q >= 14) return facade_ceiling(o, k - 14);  // only the ground: the same under every sky
    if (type != 5) return kNone;
    return q < 6 ? facade_wall_uniform(o, k) : facade_floor_uniform(o, k - 6);
  };
}

// The small openings: the tables hold to their printed rounding (0.005) plus 0.5 % under every sky,
// the sun-dependent ones included, which fixes the sun's side of the room (the tables' asymmetry).
// (Table B.1's row for sky type 3 is the errata's, its columns A–F in reverse of the printed order:
// the solve agrees with the corrected row to 0.005.)
TEST(Cie171, RoofOpening1x1) {
  run_case(roof_room(false), false, 0, roof_table(kRoof1x1), roof_exact(kRoofOpening1x1), 0.005, 0.005);
}

TEST(Cie171, FacadeOpening2x1) {
  run_case(facade_room(false), true, kGround, facade_table(kFacadeWall2x1, kFacadeFloor2x1, kFacadeCeiling2x1),
           facade_exact(kFacadeOpening2x1), 0.005, 0.005);
}

// The whole ceiling or wall open: here the published values stray from the closed forms themselves,
// most beside the opening's edge: under the uniform sky (type 5) wall point A of the open roof is
// 46.74 % in Table B.3 and 45.12 % exactly (Howell V2), façade wall point A 6.43 % against 6.18 %,
// ceiling point N' 13.59 % against 13.35 % for every sky. The result is held to the closed forms to
// 1e-6 and to the tables only to 10 %, which still tells a sun on the wrong side (the sunny skies'
// tables differ by 30 % and more from one side of the room to the other). Two table entries are left
// out: B.4's point G under sky 13 (42.07 % between 48.25 % and its mirror image's neighbours; the
// solve gives 47.01 %, a misprint of 47.07 % by every look of it) and B.13's row for sky 14, which
// the transcription gives as a copy of sky 15's (the solve's sky-15 row agrees with it to 0.5 %).
TEST(Cie171, RoofOpening4x4) {
  const TableAt table = [](int type, std::size_t q) { return type == 13 && q == 6 ? kNone : kRoof4x4[type - 1][q]; };
  run_case(roof_room(true), false, 0, table, roof_exact(kRoofOpening4x4), 0, 0.10);
}

TEST(Cie171, FacadeOpening4x3) {
  const TableAt printed = facade_table(kFacadeWall4x3, kFacadeFloor4x3, kFacadeCeiling4x3);
  const TableAt table = [&](int type, std::size_t q) { return type == 14 && q >= 6 && q < 14 ? kNone : printed(type, q); };
  run_case(facade_room(true), true, kGround, table, facade_exact(kFacadeOpening4x3), 0, 0.10);
}

}  // namespace
}  // namespace lambert
