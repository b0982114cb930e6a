// Visible fraction of a link (patch-patch, point-patch, patch-light) from ray samples. Each ray is
// weighted by the link's differential kernel at its ends, so the estimate is of the visible share of
// the flux, not of the area. Progressive: 4 rays; if they disagree 16; if those disagree 64. Fully
// visible and fully hidden links (the vast majority) cost 4 rays.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "mesh/geometry.h"
#include "solver/visibility.h"

namespace lambert {

inline constexpr int kMaxVisibilitySamples = 64;

// Stratified points on a triangle: centroids of the 64 cells of a three-level 1:4 split, ordered so
// that the first 4 lie one per level-1 cell (the three corner cells and the centre cell) and the
// first 16 one per level-2 cell.
const std::array<std::array<double, 3>, kMaxVisibilitySamples>& triangle_visibility_samples();
inline Point3 visibility_sample(const Triangle& t, int k) {
  const auto& w = triangle_visibility_samples()[k];
  return barycentric(t.v[0], t.v[1], t.v[2], w[0], w[1], w[2]);
}

// The sample of the far end paired with sample k of the near end: the first round pairs corner
// cells with corner cells (so that a patch partly covered by a nearby object, whose corners differ,
// is caught by the first four rays), the rest follow a fixed odd-multiplier permutation that pairs
// cells that do not correspond.
constexpr int paired_sample(int k) { return k < 4 ? (k + 1) % 4 : 4 + (37 * k + 11) % 60; }

// Ray k between two surface elements (receiver r with unit normal nr, source s with ns): the
// receiver's sample k and the source's paired_sample(k), each lifted off its surface (`vis`: a
// Visibility, or anything with its lift).
template <class Vis>
std::pair<Point3, Point3> element_pair_ray(const Vis& vis, const Triangle& r, const Vector3& nr, const Triangle& s,
                                           const Vector3& ns, int k) {
  return {vis.lift(visibility_sample(r, k), nr), vis.lift(visibility_sample(s, paired_sample(k)), ns)};
}

// The differential form-factor kernel cos θ_p cos θ_q / r² (up to 1/π) between two oriented points
// (p with unit normal np, q with nq); the weight of a visibility ray.
inline double link_weight(const Point3& p, const Vector3& np, const Point3& q, const Vector3& nq) {
  const Vector3 d = q - p;
  const double r2 = length_squared(d);
  return std::max(0.0, dot(np, d)) * std::max(0.0, -dot(nq, d)) / (r2 * r2);
}

// The running vote of a link's rays: visible share of the kernel weight, and whether the rays traced
// so far agree. A ray's verdict v is the share of it that arrives: 0 or 1, or a clear pane's g(θ)
// (Visibility::transmitted); the rays agree when all or none arrive.
struct VisibilityTally {
  double seen = 0, total = 0;
  int visible = 0, traced = 0;
  void add(double weight, double v) {
    ++traced;
    visible += v > 0;
    seen += weight * v;
    total += weight;
  }
  bool unanimous() const { return traced > 0 && (visible == 0 || visible == traced); }
  double fraction() const { return total > 0 ? seen / total : 1.0; }
};

// The rounds of rays: samples [0, first_round), then up to 16, then up to kMaxVisibilitySamples; a
// link stops after the first round whose rays (all so far) are unanimous.
constexpr std::array<int, 3> visibility_rounds(int first_round) { return {first_round, 16, kMaxVisibilitySamples}; }

// endpoints(k) -> {from, to} for ray k (k < 64); weight(from, to) >= 0. Each ray's verdict is
// Visibility::transmitted (through clear panes in a view, Visibility::through_panes). `first_round` rays (4 or 16)
// are traced before the first vote. Samples of zero weight
// (behind either end's horizon: the kernel has already excluded them) are not traced and do not vote:
// a link whose first samples all lie behind a horizon is not declared hidden by them. Returns 1 when
// no sample has weight (the rays cannot tell; the unoccluded factor stands).
template <class Endpoints, class Weight>
double weighted_visible_fraction(const Visibility& vis, Endpoints&& endpoints, Weight&& weight, int first_round = 4) {
  VisibilityTally tally;
  int k = 0;
  for (int round_end : visibility_rounds(first_round)) {
    for (; k < round_end; ++k) {
      const auto [from, to] = endpoints(k);
      const double w = weight(from, to);
      if (w > 0) tally.add(w, vis.transmitted(from, to));
    }
    if (tally.unanimous()) break;  // no need to refine
  }
  return tally.fraction();
}

// The same for `count` links at once (one receiver's row of links): each round's rays of all links
// still undecided go to Embree together as a stream (Visibility::estimate_visible: the fast BVH
// where the Visibility has one), which traces coherent rays about twice as fast as one call per ray.
// endpoints(l, k) and weight(l, from, to) as above for link l; fractions[l] receives the result,
// equal to weighted_visible_fraction's but where a ray passes within float precision of a seam.
// Returns the number of rays traced.
//
// Links with early_hidden[l] set (the span may be empty: none) first trace 4 rays alone and are closed
// as hidden if all 4 are blocked; otherwise they go on as the others do. For links whose whole
// unoccluded transfer is within the caller's error budget: a wrong verdict costs no more than that.
template <class Endpoints, class Weight>
std::size_t weighted_visible_fractions(const Visibility& vis, std::size_t count, Endpoints&& endpoints, Weight&& weight,
                                std::span<double> fractions, int first_round = 4,
                                std::span<const char> early_hidden = {}) {
  thread_local std::vector<VisibilityTally> tallies;
  thread_local std::vector<std::size_t> open, still_open, ray_link;
  thread_local std::vector<int> next_sample;
  thread_local std::vector<Segment> segments;
  thread_local std::vector<double> weights;
  thread_local std::vector<std::uint8_t> visible;
  tallies.assign(count, VisibilityTally{});
  next_sample.assign(count, 0);
  open.resize(count);
  for (std::size_t l = 0; l < count; ++l) open[l] = l;
  std::size_t traced = 0;
  const auto rounds = visibility_rounds(first_round);
  const std::array<int, 4> round_ends = {4, rounds[0], rounds[1], rounds[2]};
  for (int round = early_hidden.empty() ? 1 : 0; round < 4; ++round) {
    const bool early = round == 0;
    // The round's rays written in place, a ray of zero weight overwritten by the next (a branch on
    // the weight waited for its division on every ray).
    std::size_t most = 0;
    for (std::size_t l : open)
      if (!early || early_hidden[l]) most += std::max(0, round_ends[round] - next_sample[l]);
    if (segments.size() < most) segments.resize(most), weights.resize(most), ray_link.resize(most);
    std::size_t kept = 0;
    for (std::size_t l : open) {
      if (early && !early_hidden[l]) continue;
      for (int k = next_sample[l]; k < round_ends[round]; ++k) {
        const auto [from, to] = endpoints(l, k);
        const double w = weight(l, from, to);
        segments[kept] = {from, to};
        weights[kept] = w;
        ray_link[kept] = l;
        kept += w > 0;
      }
      next_sample[l] = std::max(next_sample[l], round_ends[round]);
    }
    if (visible.size() < kept) visible.resize(kept);
    vis.estimate_visible(std::span(segments.data(), kept), std::span(visible.data(), kept));
    traced += kept;
    for (std::size_t r = 0; r < kept; ++r) tallies[ray_link[r]].add(weights[r], visible[r] != 0);
    still_open.clear();
    for (std::size_t l : open) {
      const VisibilityTally& t = tallies[l];
      const bool closed = early ? early_hidden[l] && t.traced > 0 && t.visible == 0 : t.unanimous();
      if (!closed) still_open.push_back(l);
    }
    open.swap(still_open);
    if (open.empty()) break;
  }
  for (std::size_t l = 0; l < count; ++l) fractions[l] = tallies[l].fraction();
  return traced;
}

// What a hemisphere probe found (probe_hemisphere).
enum class Hemisphere : std::uint8_t {
  Open,      // a ray escaped the scene
  Closed,    // every ray met the front of a surface
  Leaking,   // some met a back face: an enclosure open underneath, or a surface facing the wrong way
  Enclosed,  // every ray met a back face: the triangle lies inside a closed solid
};

// Probes a triangle's hemisphere (unit normal n) with `rays` cosine-distributed rays: a rank-1 lattice
// (Fibonacci) in [0,1)², shifted by a hash of `seed` (Cranley–Patterson) so that neighbouring patches
// do not miss the same directions, from the triangle's stratified sample points. `hits_back(hit, d)`
// tells whether a ray along d that meets occluder `hit` meets its back (usually dot(normal, d) ≥ 0).
// Returns the verdict (Hemisphere, below). An opening that subtends a fraction p of the projected
// hemisphere goes unseen with probability (1 − p)^rays.
//
// A ray that escapes or meets a back face is traced again as two parallel twins, moved along the
// surface by 1e-5 of the scene's size in two perpendicular directions; its verdict is dropped if a
// twin meets a front face. Rays that graze an edge where two faces of a solid meet (a desk's top and
// side) can be counted as meeting the face's back at its very edge, or slip through the seam: in the
// office benchmark one probe ray in about 10⁷, enough to leave closed leaves unbalanced in a run
// with 10⁸ probe rays (furnace error 6e-3 instead of round-off). A seam or edge is a line: a twin
// moved across it misses it (the other may move along it). A real opening is wider than the offset,
// so both twins see it too, unless the ray passed within 1e-5 of the scene's size of its rim.
//
// `vis` is a Visibility, or anything with its lift, scene_extent, first_hit and first_hits (tests
// script the rays' fates with one).
template <class Tracer, class HitsBack>
Hemisphere probe_hemisphere(const Triangle& tri, const Vector3& n, std::size_t seed, int rays, const Tracer& vis,
                      HitsBack&& hits_back) {
  const Vector3 t = perpendicular(n);
  const Vector3 s = cross(n, t);
  const double reach = vis.scene_extent();
  constexpr double kGolden = 0.6180339887498949;  // (√5 − 1)/2
  constexpr double kTwoPi = 6.283185307179586;
  const double shift1 = std::fmod((seed + 1) * 0.7548776662466927, 1.0);
  const double shift2 = std::fmod((seed + 1) * 0.5698402909980532, 1.0);
  auto ray = [&](int k) {
    const double u1 = std::fmod((k + 0.5) / rays + shift1, 1.0);
    const double u2 = std::fmod(k * kGolden + shift2, 1.0);
    const double r = std::sqrt(u1), phi = kTwoPi * u2;  // cosine-weighted (Malley)
    const Vector3 d = t * (r * std::cos(phi)) + s * (r * std::sin(phi)) + n * std::sqrt(1 - u1);
    const Point3 from = vis.lift(visibility_sample(tri, k % kMaxVisibilitySamples), n);
    return Segment{from, from + d * reach};
  };
  // What a ray met: −1 nothing (it escaped), 1 a back face, 0 a front face.
  auto verdict = [&](const Segment& seg, int hit) { return hit < 0 ? -1 : (hits_back(hit, seg.to - seg.from) ? 1 : 0); };
  const double twin_offset = 0.5e-5 * reach;  // reach is twice the scene's size
  auto confirmed = [&](const Segment& seg, int v) {
    if (v == 0) return 0;
    for (const Vector3& offset : {t * twin_offset, s * twin_offset}) {
      const Segment twin{seg.from + offset, seg.to + offset};
      if (verdict(twin, vis.first_hit(twin.from, twin.to)) == 0) return 0;  // the ray met an edge or seam
    }
    return v;
  };
  // The first 16 rays one at a time (an open patch is usually found by one of the first few), the
  // rest in streams (a closed patch needs them all, and streams trace them faster).
  int back = 0;
  const int single = std::min(rays, 16);
  for (int k = 0; k < single; ++k) {
    const Segment seg = ray(k);
    const int v = confirmed(seg, verdict(seg, vis.first_hit(seg.from, seg.to)));
    if (v < 0) return Hemisphere::Open;
    back += v;
  }
  thread_local std::vector<Segment> segments;
  thread_local std::vector<int> hits;
  for (int begin = single, end = std::min(rays, 128); begin < rays; begin = end, end = rays) {
    segments.clear();
    for (int k = begin; k < end; ++k) segments.push_back(ray(k));
    hits.resize(segments.size());
    vis.first_hits(segments, hits);
    for (std::size_t r = 0; r < segments.size(); ++r) {
      const int v = confirmed(segments[r], verdict(segments[r], hits[r]));
      if (v < 0) return Hemisphere::Open;
      back += v;
    }
  }
  return back == 0 ? Hemisphere::Closed : (back == rays ? Hemisphere::Enclosed : Hemisphere::Leaking);
}

}  // namespace lambert
