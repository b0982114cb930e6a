// The UGR formula and the Guth position index (see glare.h for the sources).
#include "solver/glare.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>

namespace lambert {
namespace {

// CIE 117-1995 Table 4.1, Guth's position index: rows T/R = 0.0, 0.1, … 3.0, columns H/R = 0.0,
// 0.1, … 1.9; 0 marks the table's blank cells (above the field of view). The values are CIE 117's
// as transcribed in eulumdat-ugr (github.com/123VincentB/eulumdat-ugr, guth.py, MIT), including
// CIE 117's 7.50 at T/R 2.7, H/R 0.6, which breaks the row's rise (6.50, 7.50, 7.70; Levin's fit
// gives 6.75 there).
constexpr std::size_t kGuthRows = 31, kGuthColumns = 20;
constexpr double kGuthStep = 0.1;
constexpr std::array<std::array<double, kGuthColumns>, kGuthRows> kGuthTable{{
    {1.00, 1.26, 1.53, 1.90, 2.35, 2.86, 3.50, 4.20, 5.00, 6.00, 7.00, 8.10, 9.25, 10.35, 11.70, 13.15, 14.70, 16.20, 0, 0},  // 0.0
    {1.05, 1.22, 1.46, 1.80, 2.20, 2.75, 3.40, 4.10, 4.80, 5.80, 6.80, 8.00, 9.10, 10.30, 11.60, 13.00, 14.60, 16.10, 0, 0},  // 0.1
    {1.12, 1.30, 1.50, 1.80, 2.20, 2.66, 3.18, 3.88, 4.60, 5.50, 6.50, 7.60, 8.75, 9.85, 11.20, 12.70, 14.00, 15.70, 0, 0},  // 0.2
    {1.22, 1.38, 1.60, 1.97, 2.25, 2.70, 3.25, 3.90, 4.60, 5.45, 6.45, 7.40, 8.40, 9.50, 10.85, 12.10, 13.70, 15.00, 0, 0},  // 0.3
    {1.32, 1.47, 1.70, 1.96, 2.35, 2.80, 3.30, 3.90, 4.60, 5.40, 6.40, 7.30, 8.30, 9.40, 10.60, 11.90, 13.20, 14.60, 16.00, 0},  // 0.4
    {1.43, 1.60, 1.82, 2.10, 2.48, 2.91, 3.40, 3.98, 4.70, 5.50, 6.40, 7.30, 8.30, 9.40, 10.50, 11.75, 13.00, 14.40, 15.70, 0},  // 0.5
    {1.55, 1.72, 1.98, 2.30, 2.65, 3.10, 3.60, 4.10, 4.80, 5.50, 6.40, 7.35, 8.40, 9.40, 10.50, 11.70, 13.00, 14.10, 15.40, 0},  // 0.6
    {1.70, 1.88, 2.12, 2.48, 2.87, 3.30, 3.78, 4.30, 4.88, 5.60, 6.50, 7.40, 8.50, 9.50, 10.50, 11.70, 12.85, 14.00, 15.20, 0},  // 0.7
    {1.82, 2.00, 2.32, 2.70, 3.08, 3.50, 3.92, 4.50, 5.10, 5.75, 6.60, 7.50, 8.60, 9.50, 10.60, 11.75, 12.80, 14.00, 15.10, 0},  // 0.8
    {1.96, 2.20, 2.54, 2.90, 3.30, 3.70, 4.20, 4.75, 5.30, 6.00, 6.75, 7.70, 8.70, 9.65, 10.75, 11.80, 12.90, 14.00, 15.00, 16.00},  // 0.9
    {2.11, 2.40, 2.75, 3.10, 3.50, 3.91, 4.40, 5.00, 5.60, 6.20, 7.00, 7.90, 8.80, 9.75, 10.80, 11.90, 12.95, 14.00, 15.00, 16.00},  // 1.0
    {2.30, 2.55, 2.92, 3.30, 3.72, 4.20, 4.70, 5.25, 5.80, 6.55, 7.20, 8.15, 9.00, 9.90, 10.95, 12.00, 13.00, 14.00, 15.00, 16.00},  // 1.1
    {2.40, 2.75, 3.12, 3.50, 3.90, 4.35, 4.85, 5.50, 6.05, 6.70, 7.50, 8.30, 9.20, 10.00, 11.02, 12.10, 13.10, 14.00, 15.00, 16.00},  // 1.2
    {2.55, 2.90, 3.30, 3.70, 4.20, 4.65, 5.20, 5.70, 6.30, 7.00, 7.70, 8.55, 9.35, 10.20, 11.20, 12.25, 13.20, 14.00, 15.00, 16.00},  // 1.3
    {2.70, 3.10, 3.50, 3.90, 4.35, 4.85, 5.35, 5.85, 6.50, 7.25, 8.00, 8.70, 9.50, 10.40, 11.40, 12.40, 13.25, 14.05, 15.00, 16.00},  // 1.4
    {2.85, 3.15, 3.65, 4.10, 4.55, 5.00, 5.50, 6.20, 6.80, 7.50, 8.20, 8.85, 9.70, 10.55, 11.50, 12.50, 13.30, 14.05, 15.02, 16.00},  // 1.5
    {2.95, 3.40, 3.80, 4.25, 4.75, 5.20, 5.75, 6.30, 7.00, 7.65, 8.40, 9.00, 9.80, 10.80, 11.75, 12.60, 13.40, 14.20, 15.10, 16.00},  // 1.6
    {3.10, 3.55, 4.00, 4.50, 4.90, 5.40, 5.95, 6.50, 7.20, 7.80, 8.50, 9.20, 10.00, 10.85, 11.85, 12.75, 13.45, 14.20, 15.10, 16.00},  // 1.7
    {3.25, 3.70, 4.20, 4.65, 5.10, 5.60, 6.10, 6.75, 7.40, 8.00, 8.65, 9.35, 10.10, 11.00, 11.90, 12.80, 13.50, 14.20, 15.10, 16.00},  // 1.8
    {3.43, 3.86, 4.30, 4.75, 5.20, 5.70, 6.30, 6.90, 7.50, 8.17, 8.80, 9.50, 10.20, 11.00, 12.00, 12.82, 13.55, 14.20, 15.10, 16.00},  // 1.9
    {3.50, 4.00, 4.50, 4.90, 5.35, 5.80, 6.40, 7.10, 7.70, 8.30, 8.90, 9.60, 10.40, 11.10, 12.00, 12.85, 13.60, 14.30, 15.10, 16.00},  // 2.0
    {3.60, 4.17, 4.65, 5.05, 5.50, 6.00, 6.60, 7.20, 7.82, 8.45, 9.00, 9.75, 10.50, 11.20, 12.10, 12.90, 13.70, 14.35, 15.10, 16.00},  // 2.1
    {3.75, 4.25, 4.72, 5.20, 5.60, 6.10, 6.70, 7.35, 8.00, 8.55, 9.15, 9.85, 10.60, 11.30, 12.10, 12.90, 13.70, 14.40, 15.15, 16.00},  // 2.2
    {3.85, 4.35, 4.80, 5.25, 5.70, 6.22, 6.80, 7.40, 8.10, 8.65, 9.30, 9.90, 10.70, 11.40, 12.20, 12.95, 13.70, 14.40, 15.20, 16.00},  // 2.3
    {3.95, 4.40, 4.90, 5.35, 5.80, 6.30, 6.90, 7.50, 8.20, 8.80, 9.40, 10.00, 10.80, 11.50, 12.25, 13.00, 13.75, 14.45, 15.20, 16.00},  // 2.4
    {4.00, 4.50, 4.96, 5.40, 5.85, 6.40, 6.95, 7.55, 8.25, 8.85, 9.50, 10.05, 10.85, 11.55, 12.30, 13.00, 13.80, 14.50, 15.25, 16.00},  // 2.5
    {4.07, 4.55, 5.05, 5.47, 5.95, 6.46, 7.00, 7.65, 8.35, 8.95, 9.55, 10.10, 10.90, 11.60, 12.32, 13.00, 13.80, 14.50, 15.25, 16.00},  // 2.6
    {4.10, 4.60, 5.10, 5.53, 6.00, 6.50, 7.50, 7.70, 8.40, 9.00, 9.60, 10.16, 10.92, 11.63, 12.35, 13.00, 13.80, 14.50, 15.25, 16.00},  // 2.7
    {4.15, 4.62, 5.15, 5.56, 6.05, 6.55, 7.08, 7.73, 8.45, 9.05, 9.65, 10.20, 10.95, 11.65, 12.35, 13.00, 13.80, 14.50, 15.25, 16.00},  // 2.8
    {4.20, 4.65, 5.17, 5.60, 6.07, 6.57, 7.12, 7.75, 8.50, 9.10, 9.70, 10.23, 10.95, 11.65, 12.35, 13.00, 13.80, 14.50, 15.25, 16.00},  // 2.9
    {4.22, 4.67, 5.20, 5.65, 6.12, 6.60, 7.15, 7.80, 8.55, 9.12, 9.70, 10.23, 10.95, 11.65, 12.35, 13.00, 13.80, 14.50, 15.25, 16.00},  // 3.0
}};

}  // namespace

std::optional<double> guth_position_index_table(double h_over_r, double t_over_r) {
  double h = std::abs(h_over_r) / kGuthStep, t = std::abs(t_over_r) / kGuthStep;
  // A ratio within rounding of a node is the node (0.3 / 0.1 is 2.9999999999999996).
  if (std::abs(h - std::round(h)) < 1e-9) h = std::round(h);
  if (std::abs(t - std::round(t)) < 1e-9) t = std::round(t);
  if (!(h <= kGuthColumns - 1) || !(t <= kGuthRows - 1)) return std::nullopt;
  // The cell's lower corner, the last cell for a point on the table's far edges.
  const std::size_t j = std::min<std::size_t>(static_cast<std::size_t>(h), kGuthColumns - 2);
  const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(t), kGuthRows - 2);
  const double a = h - static_cast<double>(j), b = t - static_cast<double>(i);
  double p = 0;
  for (const auto& [di, dj, w] : {std::tuple{0, 0, (1 - b) * (1 - a)}, std::tuple{0, 1, (1 - b) * a},
                                  std::tuple{1, 0, b * (1 - a)}, std::tuple{1, 1, b * a}}) {
    if (w == 0) continue;
    const double v = kGuthTable[i + static_cast<std::size_t>(di)][j + static_cast<std::size_t>(dj)];
    if (v == 0) return std::nullopt;  // a blank corner: the cell reaches above the field of view
    p += w * v;
  }
  return p;
}

std::optional<double> guth_position_index(const Vector3& view, const Vector3& up, const Vector3& to_source) {
  const double R = dot(to_source, view);
  if (!(R > 0)) return std::nullopt;
  const Vector3 vertical = normalize(up - view * dot(up, view));
  const double H = dot(to_source, vertical);
  const double T = length(to_source - view * R - vertical * H);
  return guth_position_index_table(H / R, T / R);
}

std::optional<double> unified_glare_rating(double background_luminance_cd_m2, const std::vector<GlareSource>& sources) {
  double sum = 0;
  for (const GlareSource& s : sources) sum += s.term;
  return unified_glare_rating(background_luminance_cd_m2, sum);
}

std::optional<double> unified_glare_rating(double background_luminance_cd_m2, double sum) {
  if (!(background_luminance_cd_m2 > 0) || !(sum > 0)) return std::nullopt;
  return 8 * std::log10(0.25 / background_luminance_cd_m2 * sum);
}

}  // namespace lambert
