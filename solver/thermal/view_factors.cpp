#include "solver/thermal/view_factors.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "solver/radiosity.h"

namespace lambert {

SurfaceGroups SurfaceGroups::each_surface(const Scene& scene) {
  SurfaceGroups g;
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    g.of_surface.push_back(static_cast<int>(s));
    g.names.push_back(scene.surfaces[s].name);
  }
  return g;
}

std::vector<int> patch_groups(const TransportOperator& op, const SurfaceGroups& groups) {
  const std::vector<Patch>& patches = op.patches();
  const std::vector<Hemisphere>& hemisphere = op.hemispheres();
  std::vector<int> out(patches.size(), -1);
  for (std::size_t i = 0; i < patches.size(); ++i)
    if (hemisphere.empty() || hemisphere[i] != Hemisphere::Enclosed) out[i] = groups.of_surface.at(patches[i].surface);
  return out;
}

void measure_view_factors(ViewFactorMatrix& m) {
  const std::size_t S = m.size();
  m.row_sums.assign(S, 0.0);
  m.reciprocity_residual = 0;
  for (std::size_t I = 0; I < S; ++I)
    for (std::size_t J = 0; J < S; ++J) {
      m.row_sums[I] += m.at(I, J);
      if (J <= I || !(std::min(m.area_m2[I], m.area_m2[J]) > 0)) continue;
      const double differ = std::abs(m.area_m2[I] * m.at(I, J) - m.area_m2[J] * m.at(J, I));
      m.reciprocity_residual = std::max(m.reciprocity_residual, differ / std::min(m.area_m2[I], m.area_m2[J]));
    }
}

namespace {

// Σ_{i∈I} A_i Σ_{j occluder} F_ij / A_I: F applied once to the occluders' indicator.
std::vector<double> share_to_occluders(const TransportOperator& op, const std::vector<int>& group,
                                       const ViewFactorMatrix& m) {
  const std::size_t N = op.size();
  std::vector<double> occluder(N, 0.0), gathered(N, 0.0);
  bool any = false;
  for (std::size_t j = 0; j < N; ++j) {
    const bool hidden = !op.hemispheres().empty() && op.hemispheres()[j] == Hemisphere::Enclosed;
    occluder[j] = group[j] < 0 && !hidden ? 1.0 : 0.0;
    any = any || occluder[j] != 0;
  }
  if (!any) return {};
  op.apply({occluder.data()}, {gathered.data()});
  std::vector<double> share(m.size(), 0.0);
  for (std::size_t i = 0; i < N; ++i)
    if (group[i] >= 0) share[group[i]] += op.patches()[i].area_m2 * gathered[i];
  for (std::size_t I = 0; I < m.size(); ++I)
    if (m.area_m2[I] > 0) share[I] /= m.area_m2[I];
  return share;
}

}  // namespace

ViewFactorMatrix surface_view_factors(const TransportOperator& op, const SurfaceGroups& groups) {
  const std::size_t N = op.size(), S = groups.size();
  const std::vector<int> group = patch_groups(op, groups);
  const std::vector<Patch>& patches = op.patches();
  ViewFactorMatrix m;
  m.names = groups.names;
  m.area_m2.assign(S, 0.0);
  m.F.assign(S * S, 0.0);
  for (std::size_t i = 0; i < N; ++i)
    if (group[i] >= 0) m.area_m2[group[i]] += patches[i].area_m2;
  for (std::size_t I = 0; I < S; ++I)
    if (!(m.area_m2[I] > 0))
      m.warnings.push_back("surface \"" + m.names[I] + "\" has no area that takes part in the exchange (it lies "
                           "face to face on other surfaces or inside a closed solid): its area and factors are 0");
  // F applied to the indicator vectors of kBatch surfaces at a time: column J of the batch holds
  // Σ_{j∈J} F_ij for every patch i, summed into A_I F_IJ by i's group.
  constexpr std::size_t kBatch = 32;
  std::vector<std::vector<double>> indicator(std::min(kBatch, S), std::vector<double>(N)),
      gathered(std::min(kBatch, S), std::vector<double>(N));
  for (std::size_t J0 = 0; J0 < S; J0 += kBatch) {
    const std::size_t K = std::min(kBatch, S - J0);
    std::vector<const double*> in(K);
    std::vector<double*> out(K);
    for (std::size_t k = 0; k < K; ++k) {
      for (std::size_t j = 0; j < N; ++j) indicator[k][j] = group[j] == static_cast<int>(J0 + k) ? 1.0 : 0.0;
      in[k] = indicator[k].data();
      out[k] = gathered[k].data();
    }
    op.apply(in, out);
    for (std::size_t k = 0; k < K; ++k)
      for (std::size_t i = 0; i < N; ++i)
        if (group[i] >= 0) m.F[group[i] * S + J0 + k] += patches[i].area_m2 * gathered[k][i];
  }
  for (std::size_t I = 0; I < S; ++I)
    for (std::size_t J = 0; J < S && m.area_m2[I] > 0; ++J) m.F[I * S + J] /= m.area_m2[I];
  measure_view_factors(m);
  m.to_occluders = share_to_occluders(op, group, m);
  return m;
}

namespace {

class Fnv1a {
 public:
  void bytes(const void* data, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < n; ++k) h_ = (h_ ^ b[k]) * 1099511628211ull;
  }
  void number(double v) {
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(v == 0 ? 0.0 : v);  // 0 and −0 alike
    bytes(&bits, sizeof bits);
  }
  void whole(std::int64_t v) { bytes(&v, sizeof v); }
  void text(const std::string& s) {
    whole(static_cast<std::int64_t>(s.size()));
    bytes(s.data(), s.size());
  }
  std::uint64_t value() const { return h_; }

 private:
  std::uint64_t h_ = 1469598103934665603ull;
};

}  // namespace

std::string geometry_hash(const Scene& scene, const SurfaceGroups& groups) {
  Fnv1a h;
  h.whole(static_cast<std::int64_t>(scene.surfaces.size()));
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const Surface& surface = scene.surfaces[s];
    h.text(surface.name);
    const int g = groups.of_surface.at(s);
    h.whole(g);
    if (g >= 0) h.text(groups.names[g]);
    h.whole(static_cast<std::int64_t>(surface.mesh.vertices.size()));
    for (const Point3& v : surface.mesh.vertices) h.number(v.x), h.number(v.y), h.number(v.z);
    h.whole(static_cast<std::int64_t>(surface.mesh.triangles.size()));
    for (const auto& t : surface.mesh.triangles) h.whole(t[0]), h.whole(t[1]), h.whole(t[2]);
  }
  char text[32];
  std::snprintf(text, sizeof text, "fnv1a64:%016llx", static_cast<unsigned long long>(h.value()));
  return text;
}

}  // namespace lambert
