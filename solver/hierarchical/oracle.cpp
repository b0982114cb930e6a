#include "solver/hierarchical/oracle.h"

#include <algorithm>
#include <cmath>

namespace lambert::hierarchical {

OracleRadiosity oracle_radiosity(const Hierarchy& h, const SpectralSystems& systems,
                                 const std::vector<Hemisphere>& hemisphere, const std::vector<char>& shoots,
                                 bool with_ambient) {
  const std::size_t N = h.leaves.size(), K = systems.size();
  std::vector<double> leaf_B(N, 0.0);
  double power = 0, area = 0, rho_mean = 0;
  auto largest_rho = [&](std::size_t i) {
    double r = 0;
    for (std::size_t k = 0; k < K; ++k) r = std::max(r, std::abs(systems.reflectance(k, i)));
    return r;
  };
  for (std::size_t i = 0; i < N; ++i) {
    if (hemisphere[i] == Hemisphere::Enclosed) continue;  // neither part of the scene's power nor of its area
    for (std::size_t k = 0; k < K; ++k) leaf_B[i] = std::max(leaf_B[i], std::abs(systems.radiosity(k, i)));
    const double A = h.elements[h.leaves[i]].area;
    power += A * leaf_B[i];
    area += A;
    rho_mean += A * std::min(largest_rho(i), 0.95);
  }
  if (with_ambient && area > 0) {
    // Unlit reflectors will receive about the mean interreflected irradiance.
    rho_mean /= area;
    const double ambient = power / area / (1 - rho_mean);
    for (std::size_t i = 0; i < N; ++i) leaf_B[i] = std::max(leaf_B[i], largest_rho(i) * ambient);
  }
  // Black leaves as sources, where closed rows are known: the balance scales closed rows to 1 by
  // their sums, which include the links from black leaves. With their B of 0 the oracle would leave
  // those links as coarse as a cluster (in a black room lit by its floor the row sums missed 1 by
  // 20 %, and the floor's part moved with them). They are refined as if they sent the scene's mean
  // radiosity, from the first round on: pairs that the first round drops as within the budget
  // (B = 0 passes any test) are not found again.
  if (area > 0 && std::find(hemisphere.begin(), hemisphere.end(), Hemisphere::Closed) != hemisphere.end())
    for (std::size_t i = 0; i < N; ++i)
      if (!shoots[i]) leaf_B[i] = power / area;
  for (std::size_t i = 0; i < N; ++i)
    if (hemisphere[i] == Hemisphere::Enclosed) leaf_B[i] = 0;
  return {std::move(leaf_B), power};
}

ClusterSending cluster_sending(const Hierarchy& h, const std::vector<double>& leaf_B, std::vector<double>& largest) {
  struct RootPower {
    double largest = 0;  // the largest leaf's B
    double power = 0;    // Σ A B
    Vector3 moment;      // Σ A B x
  };
  std::vector<RootPower> root(h.elements.size());
  for (std::size_t i = 0; i < h.leaves.size(); ++i) {
    const Element& leaf = h.elements[h.leaves[i]];
    RootPower& r = root[leaf.root];
    r.largest = std::max(r.largest, leaf_B[i]);
    const double power = leaf.area * leaf_B[i];
    r.power += power;
    r.moment += power * to_vector(leaf.centre);
  }
  largest.assign(h.clusters.size(), 0.0);
  ClusterSending out;
  out.source.resize(h.clusters.size());
  out.sent.resize(h.clusters.size());
  std::vector<RootPower> below(h.clusters.size());
  for (std::size_t c = h.clusters.size(); c-- > 0;) {  // children come after their parent
    const Cluster& cl = h.clusters[c];
    SentFacets& sent = out.sent[c];
    if (cl.root >= 0) {  // a root is flat: its leaves share its normal
      below[c] = root[cl.root];
      const Vector3& n = h.elements[cl.root].normal;
      sent = {projected_bins(n, below[c].power), below[c].power * n};
    } else {
      const RootPower &a = below[cl.child[0]], &b = below[cl.child[1]];
      below[c] = {std::max(a.largest, b.largest), a.power + b.power, a.moment + b.moment};
      const SentFacets &sa = out.sent[cl.child[0]], &sb = out.sent[cl.child[1]];
      for (int k = 0; k < 6; ++k) sent.projected[k] = sa.projected[k] + sb.projected[k];
      sent.area_vector = sa.area_vector + sb.area_vector;
    }
    largest[c] = below[c].largest;
    out.source[c] = below[c].power > 0 ? to_point(below[c].moment / below[c].power) : cl.centre;
  }
  return out;
}

OracleValues oracle_values(const Hierarchy& h, const std::vector<double>& leaf_B) {
  OracleValues out;
  Hierarchy::Values v;
  h.pull({leaf_B.data()}, v);
  out.element_B = std::move(v.B);
  out.element_departure.assign(h.elements.size(), 0.0);
  for (std::size_t e = h.elements.size(); e-- > 0;) {  // children come after their parent
    const int c = h.elements[e].first_child;
    if (c < 0) continue;
    double departure = 0;
    bool open = true;  // an enclosed child's 0 is no radiosity of the field
    for (int k = 0; k < 4; ++k) {
      departure = std::max(departure, out.element_departure[c + k]);
      open = open && !h.is_enclosed(c + k);
    }
    const std::vector<double>& B = out.element_B;
    if (open) departure = std::max(departure, std::abs(B[c + 3] - (B[c] + B[c + 1] + B[c + 2]) / 3));
    out.element_departure[e] = departure;
  }
  out.sending = cluster_sending(h, leaf_B, out.cluster_B);
  return out;
}

}  // namespace lambert::hierarchical
