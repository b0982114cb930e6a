// The glare stage (see glare.h).
#include "solver/pipeline/glare.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "solver/form_factor.h"
#include "solver/rgb_model.h"
#include "solver/visible_fraction.h"

namespace lambert {
namespace {

constexpr double kSmallSourceFactor = 200;  // CIE 147: 200 I² / (r² p²)

// 683 ∫ s ȳ dλ, or the rgb model's Y.
double luminous(const std::vector<double>& s, const Scene& scene) {
  if (scene.mode == SpectrumMode::Rgb) return xyz_from_rgb_channels({s[0], s[1], s[2]}).Y;
  return luminous_integral(s, scene.grid);
}

// One luminaire's luminous parts seen from the eye, summed piece by piece.
struct Luminaire {
  bool point = false;
  double I = 0, r = 0, p = 1;           // a point source: cd, m, its position index
  double L_omega = 0, omega = 0;        // Σ L ω, Σ ω
  double L2_omega = 0, L2_omega_p2 = 0;  // Σ L² ω, Σ L² ω / p²
  double projected = 0, intensity = 0;  // Σ A_p, Σ L A_p (cd)
  Vector3 centre_dir;                   // Σ ω × unit direction
  double centre_r = 0;                  // Σ ω r

  void add_area(double L, double solid_angle, double projected_area, const Vector3& dir, double dist,
                const GlareObserver& o) {
    const auto p_index = guth_position_index(o.view, o.up, dir);
    if (!p_index || !(solid_angle > 0)) return;
    L_omega += L * solid_angle, omega += solid_angle;
    L2_omega += L * L * solid_angle, L2_omega_p2 += L * L * solid_angle / (*p_index * *p_index);
    projected += projected_area, intensity += L * projected_area;
    centre_dir += dir * solid_angle, centre_r += dist * solid_angle;
  }

  // The luminaire's GlareSource, nullopt where nothing of it is in the field.
  std::optional<GlareSource> source(const std::string& name, const GlareObserver& o) const {
    GlareSource s;
    s.source = name;
    if (point) {
      if (!(I > 0)) return std::nullopt;
      s.small = true, s.intensity_cd = I, s.distance_m = r, s.position_index = p;
      s.term = kSmallSourceFactor * I * I / (r * r * p * p);
      return s;
    }
    if (!(omega > 0)) return std::nullopt;
    s.luminance_cd_m2 = L_omega / omega;
    s.solid_angle_sr = omega;
    s.position_index = L2_omega_p2 > 0 ? std::sqrt(L2_omega / L2_omega_p2) : 1;
    s.small = projected < kSmallSourceArea_m2;
    if (!s.small) {
      s.term = L2_omega_p2;
      return s;
    }
    // CIE 147 at the parts' centre: the ω-weighted direction and distance.
    const Vector3 dir = normalize(centre_dir);
    const auto p_centre = guth_position_index(o.view, o.up, dir);
    if (!p_centre) return std::nullopt;
    s.intensity_cd = intensity;
    s.distance_m = centre_r / omega;
    s.position_index = *p_centre;
    s.term = kSmallSourceFactor * intensity * intensity / (s.distance_m * s.distance_m * *p_centre * *p_centre);
    return s;
  }
};

// The indirect illuminance at the eye on the plane facing the view, per wavelength: the gather over
// what the patches reflect (B less their Lambertian emission), and ambient light.
std::vector<double> indirect_at_eye(const GlareObserver& o, const Scene& scene, const DirectLight& light,
                                    const PointGather* gather, const SpectralSystems& systems) {
  const std::size_t W = scene.grid.size();
  std::vector<double> E(W, 0.0);
  const Receiver eye{Receiver::Kind::Planar, o.position, o.view, {}};
  if (gather) {
    std::vector<double> Ek(systems.size(), 0.0);
    gather->gather_at_point(eye, Ek.data());
    for (std::size_t w = 0; w < W; ++w) E[w] = Ek[systems.system_of(0, w)];
  }
  for (const auto& source : light.sources) {
    if (!source->directionless()) continue;
    for (std::size_t w = 0; w < W; ++w) E[w] += source->spectrum()[w];
  }
  return E;
}

// The reflected radiosity B − M of every system that the joint set uses (the others stay 0).
std::vector<std::vector<double>> reflected_radiosity(const Scene& scene, const DirectLight& light,
                                                     const SpectralSystems& systems, const SystemFields& fields) {
  const std::size_t W = scene.grid.size(), N = systems.patches();
  std::vector<std::vector<double>> out(systems.size(), std::vector<double>(N, 0.0));
  std::vector<char> done(systems.size(), 0);
  for (std::size_t w = 0; w < W; ++w) {
    const std::size_t k = systems.system_of(0, w);
    if (done[k]) continue;
    done[k] = 1;
    for (std::size_t i = 0; i < N; ++i) out[k][i] = fields.B[k][i] - light.M[i * W + w];
  }
  return out;
}

// Each emitting Lambertian surface's input triangles in front of the eye, into `luminaires`.
void add_emitting_surfaces(const GlareObserver& o, const Scene& scene, const Visibility& vis,
                           std::map<std::string, Luminaire>& luminaires) {
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const Surface& surface = scene.surfaces[s];
    if (!surface.emission || surface.emission->lobe_exponent != 1) continue;
    std::vector<double> L = surface.emission->exitance_W_m2_nm;
    for (double& v : L) v /= kPi;
    const double Lv = luminous(L, scene);
    if (!(Lv > 0)) continue;
    Luminaire& lum = luminaires[surface.pointer];
    for (std::size_t t = 0; t < surface.mesh.triangles.size(); ++t) {
      const Triangle tri = surface.mesh.triangle(t);
      const Vector3 n = tri.normal();
      const Vector3 d = tri.centroid() - o.position;
      const double dist = length(d);
      const double cos_psi = -dot(n, d) / dist;
      if (!(cos_psi > 0)) continue;
      int seen = 0;
      for (int k = 0; k < kMaxVisibilitySamples; ++k)
        seen += vis.visible(o.position, vis.lift(visibility_sample(tri, k), n));
      if (seen == 0) continue;
      const double share = static_cast<double>(seen) / kMaxVisibilitySamples;
      lum.add_area(Lv, triangle_solid_angle(o.position, tri) * share, tri.area() * cos_psi * share, d / dist, dist, o);
    }
  }
}

GlareResult observe(const GlareObserver& o, const Scene& scene, const DirectLight& light,
                    std::span<const LobedPiece> lobed, const PointGather* gather, const SpectralSystems& systems,
                    const Visibility& vis) {
  GlareResult out;
  out.name = o.name;
  out.indirect_illuminance_lx = luminous(indirect_at_eye(o, scene, light, gather, systems), scene);
  out.background_luminance_cd_m2 = out.indirect_illuminance_lx / kPi;
  std::map<std::string, Luminaire> luminaires;  // by source pointer
  std::vector<std::string> order;
  for (std::size_t s = 0; s < light.sources.size(); ++s) {
    const GlareView g = light.sources[s]->glare_view(o.position, vis);
    if (g.kind == GlareView::Kind::None) continue;
    const bool is_light = s < scene.lights.size();
    const std::string name = is_light ? scene.light_pointers[s] : scene.surfaces[lobed[s - scene.lights.size()].surface].pointer;
    Luminaire& lum = luminaires[name];
    const double S = luminous(light.sources[s]->spectrum(), scene);
    if (g.kind == GlareView::Kind::Point) {
      const auto p = guth_position_index(o.view, o.up, g.direction);
      if (!p) continue;
      lum.point = true, lum.I = S * g.intensity, lum.r = g.distance_m, lum.p = *p;
    } else {
      lum.add_area(S * g.luminance, g.solid_angle_sr, g.projected_area_m2, g.direction, g.distance_m, o);
    }
  }
  add_emitting_surfaces(o, scene, vis, luminaires);
  for (const auto& [name, lum] : luminaires)
    if (auto s = lum.source(name, o)) out.sources.push_back(std::move(*s));
  out.ugr = unified_glare_rating(out.background_luminance_cd_m2, out.sources);
  return out;
}

}  // namespace

void solve_glare(Solution& sol, const Scene& scene, const DirectLight& light, std::span<const LobedPiece> lobed,
                 const SpectralSystems& systems, const SystemFields& fields, const TransportOperator* op,
                 const Visibility& vis) {
  sol.glare.clear();
  if (scene.glare.empty()) return;
  std::vector<std::vector<double>> reflected;
  std::unique_ptr<PointGather> gather;
  if (op && !fields.B.empty()) {
    reflected = reflected_radiosity(scene, light, systems, fields);
    std::vector<const double*> B;
    for (const auto& r : reflected) B.push_back(r.data());
    gather = op->point_gather(B);
  }
  for (const GlareObserver& o : scene.glare)
    sol.glare.push_back(observe(o, scene, light, lobed, gather.get(), systems, vis));
}

}  // namespace lambert
