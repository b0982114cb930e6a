// CIE 190's standard UGR table (see ugr_table.h for the method and its sources).
#include "solver/ugr_table.h"

#include <cmath>

#include "solver/glare.h"
#include "solver/spectrum.h"

namespace lambert {
namespace {

// One standard room: its size, CIE 190 Table 4's F_GL1 … F_GL4 for its room index, and Table 5's
// transfer factors (F_T,FW, F_T,WW−1, F_T,CW) per reflectance set, in ugr_reflectances()' order.
struct Cie190Room {
  int x_h, y_h;
  std::array<double, 4> fgl;
  std::array<std::array<double, 3>, kUgrReflectances> transfer;
};

constexpr std::array<Cie190Room, kUgrRooms> kRooms{{
    {2, 2, {0.690, 0.109, 0.085, -0.016}, {{{0.220, 0.422, 0.646}, {0.188, 0.217, 0.553}, {0.198, 0.380, 0.445}, {0.172, 0.198, 0.386}, {0.157, 0.181, 0.227}}}},
    {2, 3, {0.578, 0.200, 0.127, -0.018}, {{{0.199, 0.376, 0.571}, {0.173, 0.196, 0.497}, {0.178, 0.338, 0.393}, {0.157, 0.179, 0.346}, {0.141, 0.162, 0.203}}}},
    {2, 4, {0.528, 0.218, 0.170, -0.017}, {{{0.187, 0.351, 0.531}, {0.164, 0.184, 0.465}, {0.166, 0.314, 0.365}, {0.148, 0.167, 0.324}, {0.132, 0.151, 0.190}}}},
    {2, 6, {0.485, 0.215, 0.222, -0.012}, {{{0.174, 0.322, 0.488}, {0.154, 0.171, 0.432}, {0.154, 0.287, 0.335}, {0.138, 0.155, 0.301}, {0.123, 0.139, 0.176}}}},
    {2, 8, {0.466, 0.207, 0.249, -0.006}, {{{0.167, 0.307, 0.466}, {0.149, 0.164, 0.415}, {0.147, 0.273, 0.320}, {0.133, 0.147, 0.288}, {0.118, 0.132, 0.169}}}},
    {2, 12, {0.448, 0.198, 0.272, 0.005}, {{{0.160, 0.290, 0.443}, {0.143, 0.156, 0.397}, {0.141, 0.257, 0.304}, {0.128, 0.140, 0.276}, {0.113, 0.124, 0.161}}}},
    {4, 2, {0.528, 0.218, 0.170, -0.017}, {{{0.187, 0.351, 0.531}, {0.164, 0.184, 0.465}, {0.166, 0.314, 0.364}, {0.148, 0.167, 0.324}, {0.132, 0.151, 0.190}}}},
    {4, 3, {0.448, 0.198, 0.272, 0.005}, {{{0.158, 0.295, 0.439}, {0.142, 0.159, 0.393}, {0.140, 0.263, 0.301}, {0.126, 0.143, 0.272}, {0.112, 0.128, 0.159}}}},
    {4, 4, {0.338, 0.257, 0.351, -0.018}, {{{0.142, 0.265, 0.389}, {0.129, 0.144, 0.351}, {0.125, 0.235, 0.267}, {0.114, 0.129, 0.244}, {0.100, 0.115, 0.142}}}},
    {4, 6, {0.296, 0.203, 0.449, -0.006}, {{{0.124, 0.230, 0.335}, {0.114, 0.127, 0.307}, {0.108, 0.204, 0.230}, {0.100, 0.113, 0.212}, {0.087, 0.101, 0.124}}}},
    {4, 8, {0.280, 0.165, 0.499, 0.006}, {{{0.115, 0.211, 0.307}, {0.106, 0.117, 0.283}, {0.100, 0.187, 0.211}, {0.093, 0.104, 0.196}, {0.081, 0.092, 0.114}}}},
    {4, 12, {0.264, 0.125, 0.541, 0.027}, {{{0.105, 0.190, 0.279}, {0.098, 0.106, 0.259}, {0.091, 0.167, 0.191}, {0.085, 0.094, 0.179}, {0.074, 0.083, 0.104}}}},
    {8, 4, {0.280, 0.165, 0.499, 0.006}, {{{0.115, 0.211, 0.307}, {0.106, 0.117, 0.283}, {0.100, 0.187, 0.211}, {0.093, 0.104, 0.196}, {0.081, 0.092, 0.114}}}},
    {8, 6, {0.248, 0.058, 0.628, 0.032}, {{{0.094, 0.175, 0.247}, {0.088, 0.098, 0.231}, {0.081, 0.154, 0.169}, {0.076, 0.087, 0.158}, {0.066, 0.077, 0.092}}}},
    {8, 8, {0.239, -0.012, 0.690, 0.058}, {{{0.083, 0.155, 0.215}, {0.078, 0.088, 0.203}, {0.071, 0.137, 0.147}, {0.067, 0.078, 0.140}, {0.058, 0.069, 0.081}}}},
    {8, 12, {0.232, -0.084, 0.740, 0.098}, {{{0.071, 0.133, 0.183}, {0.067, 0.076, 0.174}, {0.061, 0.117, 0.125}, {0.058, 0.067, 0.120}, {0.049, 0.059, 0.069}}}},
    {12, 4, {0.264, 0.125, 0.541, 0.027}, {{{0.105, 0.190, 0.279}, {0.098, 0.106, 0.259}, {0.091, 0.167, 0.191}, {0.085, 0.094, 0.179}, {0.074, 0.083, 0.104}}}},
    {12, 6, {0.239, -0.012, 0.690, 0.058}, {{{0.083, 0.153, 0.216}, {0.078, 0.086, 0.204}, {0.071, 0.134, 0.148}, {0.068, 0.077, 0.140}, {0.058, 0.067, 0.081}}}},
    {12, 8, {0.232, -0.084, 0.740, 0.098}, {{{0.071, 0.133, 0.183}, {0.067, 0.076, 0.174}, {0.061, 0.117, 0.125}, {0.058, 0.067, 0.120}, {0.049, 0.059, 0.069}}}},
}};

constexpr double kDegree = kPi / 180;

}  // namespace

const std::array<UgrRoom, kUgrRooms>& ugr_rooms() {
  static const std::array<UgrRoom, kUgrRooms> rooms = [] {
    std::array<UgrRoom, kUgrRooms> out;
    for (std::size_t k = 0; k < kUgrRooms; ++k) out[k] = {kRooms[k].x_h, kRooms[k].y_h};
    return out;
  }();
  return rooms;
}

const std::array<UgrReflectances, kUgrReflectances>& ugr_reflectances() {
  static const std::array<UgrReflectances, kUgrReflectances> sets{
      {{0.7, 0.5, 0.2}, {0.7, 0.3, 0.2}, {0.5, 0.5, 0.2}, {0.5, 0.3, 0.2}, {0.3, 0.3, 0.2}}};
  return sets;
}

UgrZonalFlux ugr_zonal_flux(const PhotometricDistribution& d, double candela_scale) {
  constexpr std::array<double, 4> kCosines{0.75, 0.5, 0.25, 0};  // the cones' cos γ
  UgrZonalFlux f;
  const Vector3& polar = d.polar();
  if (polar.x == 0 && polar.y == 0 && polar.z == -1) {
    for (std::size_t n = 0; n < 4; ++n) f.cumulative[n] = d.cap_flux(std::acos(kCosines[n]));
  } else {
    // dω = d(cos γ) dC: equal steps in cos γ put the cones' edges on step boundaries.
    constexpr int kSteps = 400, kPlanes = 720;
    const double du = 1.0 / kSteps, dc = 2 * kPi / kPlanes;
    double sum = 0;
    for (int s = 0; s < kSteps; ++s) {
      const double u = 1 - (s + 0.5) * du, sine = std::sqrt(1 - u * u);
      for (int c = 0; c < kPlanes; ++c) {
        const double C = (c + 0.5) * dc;
        sum += d.intensity({sine * std::cos(C), sine * std::sin(C), -u}) * du * dc;
      }
      if ((s + 1) % (kSteps / 4) == 0) f.cumulative[static_cast<std::size_t>((s + 1) / (kSteps / 4) - 1)] = sum;
    }
  }
  f.upward = d.flux() - f.cumulative[3];
  for (double& x : f.cumulative) x *= candela_scale;
  f.upward *= candela_scale;
  return f;
}

double ugr_background_luminance(const UgrZonalFlux& flux, std::size_t room, std::size_t reflectance) {
  const Cie190Room& r = kRooms.at(room);
  const auto& t = r.transfer.at(reflectance);
  double direct_plane = 0;  // Φ_DF
  for (std::size_t n = 0; n < 4; ++n) direct_plane += r.fgl[n] * flux.cumulative[n];
  const double direct_walls = flux.cumulative[3] - direct_plane;  // Φ_DW
  const double luminaires = (r.x_h / kUgrSpacingToHeight) * (r.y_h / kUgrSpacingToHeight);
  const double wall_area = 2 * kUgrHeight_m * kUgrHeight_m * (r.x_h + r.y_h);  // 2 H (X + Y)
  const double E_wid = luminaires / wall_area * (direct_plane * t[0] + direct_walls * t[1] + flux.upward * t[2]);
  return E_wid / kPi;
}

double ugr_glare_sum(const PhotometricDistribution& d, const LuminousOpening& opening, double candela_scale,
                     std::size_t room, UgrViewing viewing) {
  const Cie190Room& r = kRooms.at(room);
  const double H = kUgrHeight_m, S = kUgrSpacingToHeight * H;
  const int across = static_cast<int>(std::lround(r.x_h / kUgrSpacingToHeight));
  const int along = static_cast<int>(std::lround(r.y_h / kUgrSpacingToHeight));
  const double cos_max = std::cos(kUgrMaxGamma_deg * kDegree);
  double sum = 0;
  for (int j = 0; j < along; ++j) {
    const double R = (j + 0.5) * S;
    for (int i = 0; i < across; ++i) {
      const double T = (i + 0.5) * S - across * S / 2;
      const auto p = guth_position_index_table(H / R, T / R);
      if (!p) continue;
      const double r2 = R * R + T * T + H * H, dist = std::sqrt(r2);
      if (H / dist < cos_max) continue;
      // From the luminaire to the eye in its frame (x C0, y C90, z up): crosswise C0 points back along
      // the line of sight and C90 = up × C0 to the observer's right; endwise C90 points back.
      const Vector3 w = viewing == UgrViewing::kCrosswise ? Vector3{R, -T, -H} / dist : Vector3{T, R, -H} / dist;
      const double projected = opening.projected_area_m2(w);
      if (!(projected > 0)) continue;
      const double I = candela_scale * d.intensity(w);
      sum += I * I / (projected * r2 * *p * *p);
    }
  }
  return sum;
}

std::optional<UgrTable> standard_ugr_table(const PhotometricData& file, const PhotometricDistribution& d,
                                           double candela_scale) {
  const LuminousOpening opening(file.opening, Point3{0, 0, 0}, Vector3{1, 0, 0}, Vector3{0, 1, 0}, Vector3{0, 0, 1});
  if (!opening.is_area()) return std::nullopt;
  UgrTable table;
  table.luminous_flux_lm = candela_scale * d.flux();
  const UgrZonalFlux flux = ugr_zonal_flux(d, candela_scale);
  for (std::size_t room = 0; room < kUgrRooms; ++room) {
    const double crosswise = ugr_glare_sum(d, opening, candela_scale, room, UgrViewing::kCrosswise);
    const double endwise = ugr_glare_sum(d, opening, candela_scale, room, UgrViewing::kEndwise);
    for (std::size_t k = 0; k < kUgrReflectances; ++k) {
      const double Lb = ugr_background_luminance(flux, room, k);
      table.crosswise[room][k] = unified_glare_rating(Lb, crosswise);
      table.endwise[room][k] = unified_glare_rating(Lb, endwise);
    }
  }
  return table;
}

}  // namespace lambert
