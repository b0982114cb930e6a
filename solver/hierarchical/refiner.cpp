#include "solver/hierarchical/refiner.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "solver/cubature.h"
#include "solver/facet_bounds.h"
#include "solver/visible_fraction.h"

namespace lambert::hierarchical {
namespace {

constexpr double kWellSeparated = 1.5;  // cluster links need d ≥ 1.5 (r_source + r_receiver)
// Links into clusters need d ≥ 2.5 (r_source + r_receivers). The one-point estimate is biased low (the
// mean of 1/r² over the pair exceeds 1/d²), and every receiver under the cluster shares the bias: at
// 1.5 the city block's surface means of the benchmarks fell by 3e-4, at 2.5 by less than 1e-4.
constexpr double kReceiversSeparated = 2.5;
constexpr std::size_t kResolveBatch = 4096;  // pending links traced together (Refiner::resolve)
// The share of an element link's factor that counts as its visibility error before its rays, where
// its shaft is not proven clear: they may find it anything from hidden to wholly visible.
constexpr double kUnprovenVisibility = 0.5;
constexpr double kCachedSeparation = 1.5;  // see Refiner::leaf_exchange

template <std::size_t P>
std::array<double, 3> linear_fit(const std::array<std::array<double, 3>, P>& beta, const std::array<double, P>& f) {
  double m[3][3] = {}, r[3] = {};
  for (std::size_t q = 0; q < P; ++q)
    for (int u = 0; u < 3; ++u) {
      r[u] += beta[q][u] * f[q];
      for (int v = 0; v < 3; ++v) m[u][v] += beta[q][u] * beta[q][v];
    }
  auto det = [](const double (&x)[3][3]) {
    return x[0][0] * (x[1][1] * x[2][2] - x[1][2] * x[2][1]) - x[0][1] * (x[1][0] * x[2][2] - x[1][2] * x[2][0]) +
           x[0][2] * (x[1][0] * x[2][1] - x[1][1] * x[2][0]);
  };
  const double d = det(m);
  std::array<double, 3> a{};
  for (int c = 0; c < 3; ++c) {
    double x[3][3];
    for (int u = 0; u < 3; ++u)
      for (int v = 0; v < 3; ++v) x[u][v] = v == c ? r[u] : m[u][v];
    a[c] = det(x) / d;
  }
  return a;
}

}  // namespace

Refiner::Refiner(const Hierarchy& h, const Visibility& vis, const ExactVisibility& shafts, const PlaneVerdicts& planes,
                 const SolidShafts& solids, const OracleValues& oracle, double epsilon, double unit_area, double accuracy,
                 ExchangeCache& exchange, HiddenRoom& hidden_room)
    : h_(h), vis_(vis), shafts_(shafts), planes_(planes), solids_(solids), element_B_(oracle.element_B),
      cluster_B_(oracle.cluster_B), sending_(oracle.sending), departure_(oracle.element_departure),
      epsilon_(epsilon), unit_area_(unit_area), exchange_(exchange), hidden_room_(hidden_room) {
  // The cubature of near pairs may err by a tenth of what the oracle allows a link (relative), not
  // the dense solver's 1e-5: the city block of the benchmarks solved 1.3× faster, its radiosity
  // moving by 7e-6 of the mean (rms; 4e-4 on the worst patch) at the default accuracy 1e-3.
  near_field_.rel_tolerance = std::max(near_field_.rel_tolerance, 0.1 * accuracy);
  near_field_.abs_tolerance = std::max(near_field_.abs_tolerance, 1e-3 * accuracy);
}

void Refiner::refine_to_element(int r, int s, LinkBatch& out) const {
  const Element& R = h_.elements[r];
  const Element& S = h_.elements[s];
  if (r == s || h_.is_enclosed(r) || h_.is_enclosed(s) || !any_in_front(R.tri, R.normal, S.tri) ||
      !any_in_front(S.tri, S.normal, R.tri))
    return;
  if (!h_.has_children(r) && !h_.has_children(s)) return link_leaves(r, s, out);
  const double B = element_B_[s];
  // The point kernel at the receiver's degree-5 nodes and next to its corners (it peaks at edges
  // shared with the source), fitted by a linear function over the receiver (least squares in
  // barycentric coordinates). The link carries that linear factor, so that push-down hands each
  // child the factor at its own place; the fit's residual is the link's error.
  const TriangleRule rule = triangle_rule_degree5();
  constexpr int kPoints = 10;
  std::array<std::array<double, 3>, kPoints> beta;
  std::array<double, kPoints> f;
  std::array<Point3, kPoints> points;
  for (int q = 0; q < kPoints; ++q) {
    if (q < rule.size) {
      beta[q] = *(rule.nodes + q);
    } else {
      constexpr double t = 1e-3;
      beta[q] = {t / 3, t / 3, t / 3};
      beta[q][q - rule.size] += 1 - t;
    }
    const auto& w = beta[q];
    points[q] = barycentric(R.tri.v[0], R.tri.v[1], R.tri.v[2], w[0], w[1], w[2]);
  }
  // One batch, whose lanes give point_triangle_factor's values (10 calls one by one were 6 % of the
  // cube room's solve with solver.exact_visibility).
  point_triangle_factors(points, R.normal, S.tri, f);
  double mean = 0, hi = 0;
  for (int q = 0; q < kPoints; ++q) {
    if (q < rule.size) mean += rule.weights[q] * f[q];
    hi = std::max(hi, f[q]);
  }
  if (hi <= 0) return;
  std::array<double, 3> a = linear_fit(beta, f);
  double residual = 0;
  for (int q = 0; q < kPoints; ++q)
    residual = std::max(residual, std::abs(f[q] - (a[0] * beta[q][0] + a[1] * beta[q][1] + a[2] * beta[q][2])));
  const double weight = area_weight(R.area);
  // The kernel's fit, and the source's radiosity away from the linear field the link reads.
  if ((B * residual + mean * departure_[s]) * weight > epsilon_) return split(r, s, out);
  // Near pairs: the mean by adaptive cubature over the smaller of the two (exchange_area; exact
  // kernel, log-singular near contact).
  const double separation = distance(R.centre, S.centre) / (R.radius + S.radius);
  // (The fixed rule's mean only where S's plane does not cut R: see cubature.h, front_part.)
  const bool smooth = separation > 4 * kTie && !plane_cuts(R.tri, S.tri.v[0], S.tri.area_vector());
  const double F = smooth ? mean : exchange_area(R.tri, S.tri, near_field_) / R.area;
  if (F <= 0) return;
  const double shift = F - (a[0] + a[1] + a[2]) / 3;  // the linear factor's mean is F exactly
  for (double& value : a) value += shift;
  // Visibility. An occluder in the shaft (the hull of the two elements) makes the link uncertain
  // even when rays would agree: unanimous rays between coarse elements can miss a partly hidden part
  // (and drop a link that is half visible) or a small occluder, and a missed occluder is counted
  // twice (through the link and through the occluder's own links), which biased row sums by tens
  // of %. Half the factor bounds the error either way; where that is over the oracle's budget, a
  // clear shaft means wholly visible, exactly and without rays, and any other is split. Where it is
  // within the budget, the link takes rays (16 before the first vote) without the shaft test: in
  // the lit sphere rooms 95 % of the tested pairs were of this kind and 0.7 % of them clear, so the
  // test (9 % of the solve's time, about 40 rays' worth) mostly bought nothing. Before either, the
  // occluder planes, a few word operations: a pair they clear is wholly visible; then the solids'
  // shafts (solid_shafts.h), where no occluder but the pair's own convex solids comes near it.
  const double uncertain = kUnprovenVisibility * F;
  bool clear = planes_.clear(r, s);
  const bool unblocked = !clear && solids_.clear(r, s);
  if (!clear && !unblocked && B * uncertain * weight > epsilon_) {
    const std::array<Point3, 6> hull = {R.tri.v[0], R.tri.v[1], R.tri.v[2], S.tri.v[0], S.tri.v[1], S.tri.v[2]};
    clear = shafts_.shaft_is_clear(hull);
  }
  const double partial = clear || unblocked ? 0 : uncertain;
  if (B * partial * weight > epsilon_) return split(r, s, out);
  Link link;
  link.receiver = r;
  link.source = s;
  for (int k = 0; k < 3; ++k) link.coeff[k] = static_cast<float>(a[k]);
  link.error_per_B = static_cast<float>((residual + partial) * weight);
  if (h_.has_children(s)) link.bin = source_point_of(S, R);
  link.set_visibility(clear       ? LinkVisibility::ShaftClear
                      : unblocked ? LinkVisibility::SolidsClear
                                  : LinkVisibility::Unknown);
  if (clear || unblocked) out.links.push_back(link);
  else out.pending.push_back(link);
}

void Refiner::refine_to_cluster(int r, int c, LinkBatch& out) const {
  if (h_.is_enclosed(r)) return;
  const Element& R = h_.elements[r];
  const Cluster& C = h_.clusters[c];
  if (C.root >= 0) return refine_to_element(r, C.root, out);
  const double scale = R.radius + C.radius;
  if (!box_in_front(C.box, R.tri.v[0], R.normal, 1e-12 * scale)) return;
  const Vector3 d_vec = R.centre - C.centre;  // from the cluster to the receiver
  const double d = length(d_vec);
  const double d_min = d - C.radius - R.radius;
  if (d >= kWellSeparated * scale * kTie && d_min > 0) {
    const Vector3 w = d_vec / d;
    // Nothing passes only where no direction between the two faces both ways (see may_face); where
    // the line between the centres misses but others may not, the pair is split below, unless all
    // that could pass is within the oracle's budget.
    const double sin_delta = scale / d;
    const double cos_r = -dot(R.normal, w);
    if (cos_r <= -sin_delta || !may_face(C, w, sin_delta, bounds(R.tri))) return;
    const ClusterView view = cluster_view(h_, c, w, sin_delta, &sending_.sent);
    // A link of factor 0 where the line between the centres misses: dropped if all that could pass
    // along the other directions is within the budget.
    if ((view.projected <= 0 || cos_r <= 0) &&
        cluster_B_[c] * unseen_transfer(C, view, cos_r > 0, sin_delta, d_min) * area_weight(R.area) <= epsilon_)
      return;
    if (view.projected > 0 && cos_r > 0 && !reads_any_radiosity(C, w)) {
      // Its children are linked instead, down to clusters whose bins read any radiosity, or roots.
      for (int ch : C.child) {
        refine_to_cluster(r, ch, out);
        resolve_if_full(out);
      }
      return;
    }
    const double error_per_B = one_point_error(view, scale, d, d_min) * area_weight(R.area);
    if (view.projected > 0 && cos_r > 0 && cluster_B_[c] * error_per_B <= epsilon_) {
      Link link;
      link.receiver = r;
      link.source = c;
      link.from_cluster = true;
      link.bin = view.bin;
      const std::array<double, 3> factor = receiver_mean_factors(view, w, sending_.source[c], R.tri, R.normal);
      for (int a = 0; a < 3; ++a) link.coeff[a] = static_cast<float>(factor[a]);
      link.error_per_B = static_cast<float>(error_per_B);
      if (planes_.clear_cluster(c, r, false) || solids_.clear_cluster(c, r, false))
        out.links.push_back(link);  // wholly visible, no rays
      else out.pending.push_back(link);
      return;
    }
  }
  if (C.radius * kTie >= R.radius || !h_.has_children(r)) {
    for (int ch : C.child) {
      refine_to_cluster(r, ch, out);
      resolve_if_full(out);
    }
  } else {
    const int first = h_.elements[r].first_child;
    for (int k = 0; k < 4; ++k) {
      refine_to_cluster(first + k, c, out);
      resolve_if_full(out);
    }
  }
}

void Refiner::refine_pair(int rc, int s, bool from_cluster, LinkBatch& out) const {
  const Cluster& R = h_.clusters[rc];
  if (R.root >= 0) {
    from_cluster ? refine_to_cluster(R.root, s, out) : refine_to_element(R.root, s, out);
    resolve_if_full(out);
    return;
  }
  if (from_cluster && h_.clusters[s].root >= 0) return refine_pair(rc, h_.clusters[s].root, false, out);
  const Point3& s_centre = from_cluster ? h_.clusters[s].centre : h_.elements[s].centre;
  const double s_radius = from_cluster ? h_.clusters[s].radius : h_.elements[s].radius;
  auto split_receiver = [&] {
    refine_pair(R.child[0], s, from_cluster, out);
    refine_pair(R.child[1], s, from_cluster, out);
  };
  auto split = [&] {
    if (R.radius * kTie >= s_radius || (!from_cluster && !h_.has_children(s))) return split_receiver();
    if (from_cluster) {
      for (int c : h_.clusters[s].child) refine_pair(rc, c, true, out);
    } else {
      for (int k = 0; k < 4; ++k) refine_pair(rc, h_.elements[s].first_child + k, false, out);
    }
  };
  const double scale = R.radius + s_radius;
  const Vector3 between = R.centre - s_centre;  // from the source to the receivers
  const double d = length(between);
  const double d_min = d - scale;
  if ((from_cluster && rc == s) || d < kReceiversSeparated * scale * kTie || d_min <= 0) return split();
  if (R.cone_sin > 1) return split_receiver();
  const Vector3 w = between / d;
  // α: between the receivers' cone axis and u = −w; θ: the cone's half-angle; δ: how far the
  // directions between points of the two bounding spheres stray from u.
  const double alpha = std::acos(std::clamp(-dot(R.cone_axis, w), -1.0, 1.0));
  const double theta = std::asin(R.cone_sin);
  const double delta = std::asin(std::min(1.0, scale / d));
  if (alpha - theta - delta >= kPi / 2) return;  // every receiver faces away from every source point
  // The source: nothing passes where none of it faces any direction of the cone (may_face); where
  // only the line between the centres misses it, the pair is split unless all that could pass is
  // within the oracle's budget.
  const double sin_delta = std::min(1.0, scale / d);
  ClusterView view;
  if (from_cluster) {
    if (!may_face(h_.clusters[s], w, sin_delta, R.box)) return;
    view = cluster_view(h_, s, w, sin_delta, &sending_.sent);
    if (view.projected > 0 && !reads_any_radiosity(h_.clusters[s], w)) {  // as refine_to_cluster
      for (int c : h_.clusters[s].child) refine_pair(rc, c, true, out);
      return;
    }
  } else {
    const Element& E = h_.elements[s];
    if (dot(E.normal, w) <= -sin_delta) return;
    view.projected = E.area * std::max(0.0, dot(E.normal, w));
    view.turning = turning_area(E.area, dot(E.normal, w), sin_delta);
  }
  const double B = from_cluster ? cluster_B_[s] : element_B_[s];
  const double weight = area_weight(R.area);
  const double shown = from_cluster ? max_projected(h_.clusters[s]) : h_.elements[s].area;  // along any direction
  // Where α + θ + δ > π/2 a receiver's horizon may cut the source (horizon_cut_error).
  const double excess = alpha + theta + delta - kPi / 2;
  const double clipped = excess > 0 ? horizon_cut_error(std::sin(excess), shown, d_min) * weight : 0;
  if (!from_cluster && alpha + theta <= kPi / 2 && dot(h_.elements[s].normal, w) >= sin_delta) {
    if (B * clipped > epsilon_) return split_receiver();
    const double error_per_B = vector_estimate_error(h_.elements[s].area, R.radius, d - s_radius) * weight + clipped;
    return B * error_per_B > epsilon_ ? split() : link_vector_estimate(rc, s, error_per_B, out);
  }
  if (view.projected <= 0) {  // a link of factor 0, as in refine_to_cluster
    const double reach = shown * sin_delta / (kPi * d_min * d_min) * weight;
    return B * reach <= epsilon_ ? void() : split();
  }
  const double error_per_B = one_point_error(view, scale, d, d_min) * weight + clipped;
  if (alpha + theta > kPi / 2 || B * clipped > epsilon_) return split_receiver();
  if (B * error_per_B > epsilon_) return split();
  ClusterLink link;
  link.receiver = rc;
  link.source = s;
  link.from_cluster = from_cluster;
  link.bin = view.bin;
  Vector3 toward = -w;
  if (from_cluster) {
    const std::array<double, 3> factor = receivers_factors(view, w, R.centre, sending_.source[s], toward);
    for (int a = 0; a < 3; ++a) link.coeff[a] = static_cast<float>(factor[a]);
  } else {
    link.coeff[0] = static_cast<float>(view.projected / (kPi * d * d));
  }
  link.toward = {static_cast<float>(toward.x), static_cast<float>(toward.y), static_cast<float>(toward.z)};
  link.error_per_B = static_cast<float>(error_per_B);
  link.proven_visible = planes_.clear_cluster(rc, s, from_cluster) || solids_.clear_cluster(rc, s, from_cluster);
  if (link.proven_visible) out.cluster_links.push_back(link);  // wholly visible, no rays
  else out.cluster_pending.push_back(link);
}

void Refiner::link_vector_estimate(int rc, int s, double error_per_B, LinkBatch& out) const {
  const Vector3 V = triangle_vector_factor(h_.clusters[rc].centre, h_.elements[s].tri);
  const double F = length(V);
  if (!(F > 0)) return;
  ClusterLink link;
  link.receiver = rc;
  link.source = s;
  link.coeff[0] = static_cast<float>(F);
  link.toward = {static_cast<float>(V.x / F), static_cast<float>(V.y / F), static_cast<float>(V.z / F)};
  link.error_per_B = static_cast<float>(error_per_B);
  link.proven_visible = planes_.clear_cluster(rc, s, false) || solids_.clear_cluster(rc, s, false);
  if (link.proven_visible) out.cluster_links.push_back(link);  // wholly visible, no rays
  else out.cluster_pending.push_back(link);
}

void Refiner::resolve(LinkBatch& out) const {
  resolve_cluster_links(out);
  // Pairs that their rays found partly visible and over the budget are split (resolve_pending), and
  // their children may wait for rays in turn (split adds to out.pending and never resolves).
  std::vector<std::pair<int, int>> resplit;
  while (!out.pending.empty()) {
    resplit.clear();
    resolve_pending(out, resplit);
    for (const auto& [r, s] : resplit) split(r, s, out);
  }
}

void Refiner::resolve_pending(LinkBatch& out, std::vector<std::pair<int, int>>& resplit) const {
  thread_local std::vector<double> fraction;
  fraction.resize(out.pending.size());
  // Links whose whole unoccluded transfer is within the oracle's budget ε may be found hidden by 4
  // rays (weighted_visible_fractions): a wrong verdict errs by no more than a link may.
  thread_local std::vector<char> early;
  early.resize(out.pending.size());
  for (std::size_t l = 0; l < out.pending.size(); ++l) {
    const Link& link = out.pending[l];
    double transfer = 0;  // irradiance at the receiver per its area weight, unoccluded
    if (link.from_cluster) {
      const Cluster& C = h_.clusters[link.source];
      for (int a = 0; a < 3; ++a) transfer += link.coeff[a] * bin_value(C.projected.data(), link.bin[a], 1, 0);
      transfer *= cluster_B_[link.source];
    } else if (!factor_pending(link)) {
      transfer = element_B_[link.source] * (link.coeff[0] + link.coeff[1] + link.coeff[2]) / 3;
    } else {
      // Two leaves, whose factor is computed after the rays: twice the point factor at the
      // receiver's centroid stands for it, for pairs whose bounding spheres are well apart.
      const Element& R = h_.elements[link.receiver];
      const Element& S = h_.elements[link.source];
      const bool apart = distance(R.centre, S.centre) > 2 * (R.radius + S.radius) * kTie;
      transfer = apart ? 2 * element_B_[link.source] * point_triangle_factor(R.centre, R.normal, S.tri) : 1e300;
    }
    early[l] = transfer * area_weight(h_.elements[link.receiver].area) <= epsilon_;
  }
  Vector3 source_normal;  // of the sample just drawn (weight() follows endpoints() for each ray)
  out.rays += weighted_visible_fractions(
      vis_, out.pending.size(),
      [&](std::size_t l, int k) {
        const Link& link = out.pending[l];
        const Element& R = h_.elements[link.receiver];
        if (link.from_cluster) {
          const ClusterTree::ClusterSample S = cluster_sample(h_, h_.clusters[link.source], k);
          source_normal = S.normal;
          return std::pair{vis_.lift(visibility_sample(R.tri, k), R.normal), vis_.lift(S.point, S.normal)};
        }
        const Element& S = h_.elements[link.source];
        source_normal = S.normal;
        return element_pair_ray(vis_, R.tri, R.normal, S.tri, S.normal, k);
      },
      [&](std::size_t l, const Point3& p, const Point3& q) {
        return link_weight(p, h_.elements[out.pending[l].receiver].normal, q, source_normal);
      },
      fraction, 16, early);
  for (std::size_t l = 0; l < out.pending.size(); ++l) {
    const Link& traced = out.pending[l];
    // A link its rays found partly visible or hidden gives every leaf below its receiver the same
    // visible fraction v, where a leaf may see all of the source or none of it: the leaf's error is up
    // to F max(v, 1 − v), F where every ray was blocked, not the F / 2 that refine_to_element budgeted
    // before the rays. Over the budget the pair is split. (Hidden pairs dropped within 2ε each err
    // with one sign, and add up in a room that gathers a small share of the scene's mean, lit through
    // a door: docs/BENCHMARKS.md, "A dim room beside a bright one".)
    const double v = fraction[l];
    const double weight = area_weight(h_.elements[traced.receiver].area);
    double visibility_error = 0;  // per unit B
    if (v < 1 && !traced.from_cluster && !factor_pending(traced)) {
      visibility_error = traced.mean_factor() * std::max(v, 1 - v) * weight;
      if (element_B_[traced.source] * visibility_error > epsilon_) {
        resplit.emplace_back(traced.receiver, traced.source);
        continue;
      }
    }
    if (!(v > 0)) {
      if (keeps_hidden(traced.from_cluster, traced.from_cluster, traced.source) ||
          (factor_pending(traced) && !early[l] && keeps_bright_hidden(bright_leaves(traced))))
        out.hidden.push_back(traced);
      continue;
    }
    Link link = traced;
    if (visibility_error > 0) {
      // error_per_B holds refine_to_element's kUnprovenVisibility F: the rest of the bound joins it.
      link.error_per_B =
          static_cast<float>(link.error_per_B + visibility_error - kUnprovenVisibility * link.mean_factor() * weight);
    }
    if (factor_pending(link)) {  // two leaves (link_leaves): the mean factor, now
      const double F = leaf_exchange(link.receiver, link.source) / h_.elements[link.receiver].area;
      if (!(F > 0)) continue;
      link.coeff.fill(static_cast<float>(F));
    }
    for (float& c : link.coeff) c = static_cast<float>(c * fraction[l]);
    if (!link.from_cluster && fraction[l] == 1) link.set_visibility(LinkVisibility::RaysUnanimous);
    out.links.push_back(link);
  }
  out.pending.clear();
}

void Refiner::resolve_cluster_links(LinkBatch& out) const {
  if (out.cluster_pending.empty()) return;
  thread_local std::vector<double> fraction;
  fraction.resize(out.cluster_pending.size());
  Vector3 receiver_normal, source_normal;  // of the samples just drawn
  out.rays += weighted_visible_fractions(
      vis_, out.cluster_pending.size(),
      [&](std::size_t l, int k) {
        const ClusterLink& link = out.cluster_pending[l];
        const ClusterTree::ClusterSample R = cluster_sample(h_, h_.clusters[link.receiver], k);
        receiver_normal = R.normal;
        const Point3 p = vis_.lift(R.point, R.normal);
        if (link.from_cluster) {
          const ClusterTree::ClusterSample S = cluster_sample(h_, h_.clusters[link.source], paired_sample(k));
          source_normal = S.normal;
          return std::pair{p, vis_.lift(S.point, S.normal)};
        }
        const Element& S = h_.elements[link.source];
        source_normal = S.normal;
        return std::pair{p, vis_.lift(visibility_sample(S.tri, paired_sample(k)), S.normal)};
      },
      [&](std::size_t, const Point3& p, const Point3& q) { return link_weight(p, receiver_normal, q, source_normal); },
      fraction, 16);
  for (std::size_t l = 0; l < out.cluster_pending.size(); ++l) {
    if (!(fraction[l] > 0)) {
      if (keeps_hidden(true, out.cluster_pending[l].from_cluster, out.cluster_pending[l].source))
        out.hidden_cluster.push_back(out.cluster_pending[l]);
      continue;
    }
    ClusterLink link = out.cluster_pending[l];
    for (float& c : link.coeff) c = static_cast<float>(c * fraction[l]);
    out.cluster_links.push_back(link);
  }
  out.cluster_pending.clear();
}

bool Refiner::keeps_hidden(bool clustered, bool from_cluster, int source) const {
  if (from_cluster && h_.clusters[source].root_count > kExpandedClusterRoots) return false;
  std::atomic<std::int64_t>& room = clustered ? hidden_room_.clustered : hidden_room_.elements;
  return room.load(std::memory_order_relaxed) > 0 && room.fetch_sub(1, std::memory_order_relaxed) > 0;
}

bool Refiner::bright_leaves(const Link& link) const {
  return bright_leaf_pair(h_.elements[link.receiver], h_.elements[link.source], element_B_[link.source], epsilon_);
}

bool Refiner::keeps_bright_hidden(bool bright) const {
  std::atomic<std::int64_t>& room = hidden_room_.bright_leaves;
  return bright && room.load(std::memory_order_relaxed) > 0 && room.fetch_sub(1, std::memory_order_relaxed) > 0;
}

bool Refiner::recheck(const ClusterLink& link, LinkBatch& out) const {
  const double B = link.from_cluster ? cluster_B_[link.source] : element_B_[link.source];
  if (B * link.error_per_B <= epsilon_) return false;
  refine_pair(link.receiver, link.source, link.from_cluster, out);
  return true;
}

bool Refiner::recheck(const Link& link, LinkBatch& out) const {
  const double B = link.from_cluster ? cluster_B_[link.source] : element_B_[link.source];
  const double departure =
      link.from_cluster ? 0 : link.mean_factor() * departure_[link.source] * area_weight(h_.elements[link.receiver].area);
  if (B * link.error_per_B + departure <= epsilon_) return false;
  if (link.from_cluster) {
    refine_to_cluster(link.receiver, link.source, out);
  } else if (h_.has_children(link.receiver) || h_.has_children(link.source)) {
    split(link.receiver, link.source, out);
  } else {
    return false;  // leaves both: nothing finer to link
  }
  return true;
}

void Refiner::link_leaves(int r, int s, LinkBatch& out) const {
  Link link;
  link.receiver = r;
  link.source = s;
  const bool clear = planes_.clear(r, s);
  if (clear || solids_.clear(r, s)) {
    const double F = leaf_exchange(r, s) / h_.elements[r].area;
    if (!(F > 0)) return;
    link.coeff.fill(static_cast<float>(F));
    link.set_visibility(clear ? LinkVisibility::ShaftClear : LinkVisibility::SolidsClear);
    out.links.push_back(link);
    return;
  }
  link.coeff.fill(kFactorPending);
  out.pending.push_back(link);
}

double Refiner::leaf_exchange(int r, int s) const {
  const Element& R = h_.elements[r];
  const Element& S = h_.elements[s];
  if (distance(R.centre, S.centre) > kCachedSeparation * (R.radius + S.radius))
    return exchange_area(R.tri, S.tri, near_field_);
  const std::uint64_t key = (static_cast<std::uint64_t>(std::min(r, s)) << 32) | static_cast<std::uint32_t>(std::max(r, s));
  if (const auto found = exchange_.find(key); found != exchange_.end()) return found->second;
  const double value = exchange_area(R.tri, S.tri, near_field_);
  exchange_.emplace(key, value);
  return value;
}

void Refiner::split(int r, int s, LinkBatch& out) const {
  const Element& R = h_.elements[r];
  const Element& S = h_.elements[s];
  const bool split_receiver = h_.has_children(r) && (!h_.has_children(s) || R.area * kTie >= S.area);
  for (int k = 0; k < 4; ++k) {
    split_receiver ? refine_to_element(R.first_child + k, s, out) : refine_to_element(r, S.first_child + k, out);
    resolve_if_full(out);
  }
}

void Refiner::resolve_if_full(LinkBatch& out) const {
  if (out.pending.size() + out.cluster_pending.size() >= kResolveBatch) resolve(out);
}

}  // namespace lambert::hierarchical
