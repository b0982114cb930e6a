// Exact partial visibility by central projection and 2D subtraction of convex shadows; see
// exact_visibility.h.
//
// For a receiving point p (unit normal n) and a source triangle S with unit normal n_s, let
// h(q) = n_s · (q − s_0) be a point's height over S's plane, and h = h(p) > 0. A point q occludes part
// of S iff it lies in the cone from p over S, strictly above S's plane (h(q) > 0) and strictly in
// front of p's horizon (n · (q − p) > 0): segments from p to the part of S in front of the horizon
// never leave that half-space. Each occluding triangle is clipped to that region (Sutherland–Hodgman
// in double precision: a convex polygon of at most 8 vertices) and projected from p onto S's plane,
// y = p + (q − p) h / (h − h(q)); a convex polygon stays convex under this projection because all
// its points lie on S's side of the plane through p parallel to S. The cone is taken over S enlarged
// by 5 % about its centroid, so that no projected edge is made to coincide with an edge of S by
// rounding; the difference with S then cuts at S's edges.
//
// The projections are subtracted from S (clipped at p's horizon): a few by inclusion–exclusion over
// their convex intersections (signed convex loops), more by peeling S shadow by shadow into disjoint
// convex pieces (mesh/convex2d.h), or by CGAL's Polygon_set_2 with exact constructions
// (mesh/polygon_boolean.h, where asked: the tests' reference); the visible factor is the signed
// contour sum over the loops of the result.
//
// Where the occluding parts are seen in directions that do not overlap (one triangle, or the front
// faces of one convex solid), no union is needed. The factor they hide is the sum of the factors of
// their parts inside the exact cone from p over S's front (hidden_factor: the contour sum of a
// polygon depends only on the directions it covers, so the part need not be projected). For many
// sources in one plane (Shadow), the parts are projected onto the plane once, group by group; each
// group's convex hull is then its union, the hulls of all groups are united once as disjoint convex
// pieces, and each source sums the factors of its parts of the pieces.
#include "solver/exact_visibility.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

#include "mesh/convex2d.h"
#include "mesh/polygon_boolean.h"
#include "solver/exact_visibility_impl.h"
#include "solver/form_factor.h"

namespace lambert {
namespace {

// Inclusion–exclusion over convex counter-clockwise loops: visit(current, sign), then for every
// clipper k ≥ next whose intersection with `current` is not empty (area above `negligible`), the same
// for that intersection with the opposite sign and clippers after k; an empty intersection prunes
// all its supersets. From a loop S with sign +1 the terms are S ∩ A_K with sign (−1)^|K|, whose sum
// is S ∖ ∪A_k. `level` has a buffer for every depth (count of them), made by the caller.
template <class Clipper, class Visit>
void inclusion_exclusion(std::size_t count, const Clipper& clipper, const Loop2d& current, std::size_t next,
                         double sign, double negligible, std::vector<Loop2d>& level, std::size_t depth,
                         Loop2d& scratch, const Visit& visit) {
  visit(current, sign);
  for (std::size_t k = next; k < count; ++k) {
    Loop2d& part = level[depth];  // `current` is level[depth − 1] (or the caller's)
    clip_convex_into(current, clipper(k), part, scratch);
    if (part.size() < 3 || std::abs(signed_area(part)) <= negligible) continue;
    inclusion_exclusion(count, clipper, part, k + 1, -sign, negligible, level, depth + 1, scratch, visit);
  }
}

}  // namespace

ExactVisibility::ExactVisibility(std::span<const Triangle> occluders, std::span<const int> solid,
                                 std::span<const char> convex, std::span<const SolidCap> caps)
    : impl_(std::make_unique<Impl>()) {
  Bounds3 all;
  for (const Triangle& t : occluders)
    for (const Point3& v : t.v) all.add(v);
  impl_->centre = all.empty() ? Point3{} : all.center();
  const Vector3 shift = to_vector(impl_->centre);
  std::vector<Point3> centroids;
  for (std::size_t k = 0; k < occluders.size(); ++k) {
    const Triangle& t = occluders[k];
    const Triangle local{{t.v[0] - shift, t.v[1] - shift, t.v[2] - shift}};
    if (!(local.area() > 0)) continue;
    impl_->triangles.push_back(local);
    const int id = k < solid.size() ? solid[k] : -1;
    impl_->outward_solid.push_back(id >= 0);
    impl_->convex_solid.push_back(id >= 0 && static_cast<std::size_t>(id) < convex.size() && convex[id] ? id : -1);
    impl_->solid_of.push_back(id);
    centroids.push_back(local.centroid());
    if (id >= 0 && static_cast<std::size_t>(id) < caps.size() && caps[id].open) {
      if (impl_->open.size() <= static_cast<std::size_t>(id)) impl_->open.resize(id + 1);
      Impl::Open& o = impl_->open[id];
      o.open = true;
      o.normal = normalize(caps[id].normal);
      o.point = caps[id].point - shift;
      o.tolerance = std::max(o.tolerance, 1e-9 * std::sqrt(local.area()));
      const Vector3 normal = normalize(local.area_vector());
      const bool known = std::any_of(o.faces.begin(), o.faces.end(), [&](const auto& f) {
        return dot(f.first, normal) > 1 - 1e-12 && std::abs(dot(f.first, local.v[0] - f.second)) <= o.tolerance;
      });
      if (!known) o.faces.emplace_back(normal, local.v[0]);
    }
  }
  // An open solid with more face planes than the check per point should cost is no solid here.
  for (std::size_t k = 0; k < impl_->triangles.size(); ++k) {
    const int id = impl_->solid_of[k];
    if (id >= 0 && static_cast<std::size_t>(id) < impl_->open.size() && impl_->open[id].faces.size() > Impl::kMaxOpenFacePlanes)
      impl_->solid_of[k] = -1, impl_->outward_solid[k] = 0, impl_->convex_solid[k] = -1;
  }
  impl_->order.resize(impl_->triangles.size());
  std::iota(impl_->order.begin(), impl_->order.end(), 0);
  if (!impl_->triangles.empty()) impl_->build(0, static_cast<int>(impl_->triangles.size()), centroids);
  impl_->build_grid(centroids);
}

ExactVisibility::~ExactVisibility() = default;

namespace {

// What a point p sees of a source S (both relative to the occluders' centre): S's plane (unit normal
// ns, p's height h over it), the part of S in front of p's horizon, and the region that can occlude.
struct Frame {
  Point3 p;
  Triangle S;
  Vector3 ns;
  double h = 0;
  std::array<Point3, 4> front;  // the part of S in front of p's horizon: a triangle clipped by one plane
  int front_count = 0;
  std::array<HalfSpace, 6> region;
};

// False where p does not see S's front (p behind or in S's plane, or S wholly below p's horizon).
bool make_frame(const Point3& p, const Vector3& n, const Triangle& S, Frame& f) {
  const Vector3 area_vector = S.area_vector();
  if (!(length(area_vector) > 0)) return false;
  f.p = p, f.S = S;
  f.ns = normalize(area_vector);
  const Point3& s0 = S.v[0];
  f.h = dot(f.ns, p - s0);
  if (!(f.h > 0)) return false;
  const Point3 c = S.centroid();
  const double scale = distance(p, c) + S.bounding_radius();
  f.front_count = clip(S.v.data(), 3, HalfSpace{n, p, 0}, f.front.data());
  if (f.front_count < 3) return false;
  // The cone from p over S enlarged by 5 %, above S's plane (by a margin relative to h: occluders in
  // S's own plane, i.e. S's surface and its coplanar neighbours, do not occlude), in front of p's
  // horizon, below p's height.
  for (int e = 0; e < 3; ++e) {
    const Point3 a = c + (S.v[e] - c) * 1.05, b = c + (S.v[(e + 1) % 3] - c) * 1.05;
    Vector3 m = cross(a - p, b - p);
    if (dot(m, c - p) < 0) m = -m;
    f.region[e] = HalfSpace{m, p, 0};
  }
  f.region[3] = HalfSpace{f.ns, s0, 1e-9 * f.h};
  f.region[4] = HalfSpace{n, p, 1e-12 * scale};
  f.region[5] = HalfSpace{-f.ns, s0, -f.h * (1 - 1e-12)};
  return true;
}

Triangle shifted(const Triangle& t, const Vector3& shift) { return {{t.v[0] - shift, t.v[1] - shift, t.v[2] - shift}}; }

// The cone from p over the front part of S, exactly (not enlarged), and S's plane with the region's
// margin: the part of an occluder inside it hides the directions of S it is seen in. A part lies in
// front of p's horizon and below p's height by the cone's construction. Returns the planes' count.
int make_cone(const Frame& f, std::array<HalfSpace, 5>& cone) {
  const int edges = f.front_count;
  Point3 inside = f.front[0];
  for (int i = 1; i < edges; ++i) inside = inside + (f.front[i] - f.front[0]) / edges;
  for (int e = 0; e < edges; ++e) {
    Vector3 m = cross(f.front[e] - f.p, f.front[(e + 1) % edges] - f.p);
    if (dot(m, inside - f.p) < 0) m = -m;
    cone[e] = HalfSpace{m, f.p, 0};
  }
  cone[edges] = f.region[3];
  return edges + 1;
}

constexpr int kNoGroup = std::numeric_limits<int>::min();

}  // namespace

ExactVisibility::VisibleRegion ExactVisibility::visible_region(const Point3& p_world, const Vector3& n,
                                                              const Triangle& source_world) const {
  return visible_region(p_world, n, source_world, true);
}

ExactVisibility::VisibleRegion ExactVisibility::visible_region(const Point3& p_world, const Vector3& n,
                                                              const Triangle& source_world, bool count) const {
  VisibleRegion out;
  const Vector3 shift = to_vector(impl_->centre);
  Frame f;
  if (!make_frame(p_world - shift, n, shifted(source_world, shift), f)) return out;
  const Point3& p = f.p;
  const Point3& s0 = f.S.v[0];
  out.p_ = p_world;
  out.n_ = n;
  out.origin_ = source_world.v[0];
  out.e1_ = normalize(f.S.v[1] - s0);
  out.e2_ = cross(f.ns, out.e1_);
  auto to_plane = [&](const Point3& y) { return Point2d{dot(y - s0, out.e1_), dot(y - s0, out.e2_)}; };
  std::vector<Loop2d> shadows;
  thread_local ClipBuffers buffers;
  impl_->query(f.region, [&](int k) {
    const Triangle& t = impl_->triangles[k];
    // The corners decide for most triangles, as in shaft_is_clear: no shadow, or the whole triangle;
    // only the rest are clipped.
    const int verdict = impl_->verdict(k, p, f.S, f.region);
    if (verdict < 0) return false;
    const std::span<const Point3> part =
        verdict > 0 ? std::span<const Point3>(t.v.data(), 3) : clip_to_region(t, f.region, buffers);
    if (part.size() < 3) return false;
    Loop2d shadow(part.size());
    for (std::size_t i = 0; i < part.size(); ++i) {
      const Point3& q = part[i];
      shadow[i] = to_plane(p + (q - p) * (f.h / (f.h - dot(f.ns, q - s0))));
    }
    shadows.push_back(std::move(shadow));
    return false;
  });

  Loop2d source(f.front_count);
  for (int i = 0; i < f.front_count; ++i) source[i] = to_plane(f.front[i]);
  if (shadows.empty()) {
    out.loops_.push_back(std::move(source));
    return out;
  }
  if (count) occluded_.fetch_add(1, std::memory_order_relaxed);
  booleans_.fetch_add(1, std::memory_order_relaxed);
  // A few shadows (the usual case: a box seen from a point casts two to six): inclusion–exclusion over
  // convex intersections; many: the source peeled shadow by shadow into disjoint convex pieces, whose
  // cost does not grow as 2^k. Both in doubles; CGAL's exact difference where the caller asks for it.
  // Both clip by the shadows' edges: corners that the cone's clip left nearly coincident would give
  // an edge of no direction, which cut at random (a source taken as wholly hidden where a third of it
  // was seen), so each shadow is made strictly convex first.
  for (Loop2d& shadow : shadows) {
    if (signed_area(shadow) < 0) std::reverse(shadow.begin(), shadow.end());
    tidy_convex(shadow);
  }
  std::erase_if(shadows, [](const Loop2d& shadow) { return shadow.empty(); });
  const double negligible = 1e-15 * std::abs(signed_area(source));
  if (shadows.size() <= static_cast<std::size_t>(inclusion_exclusion_limit_)) {
    // S ∖ ∪A_k as signed convex loops: negative terms stored clockwise, so the contour sum subtracts them.
    std::vector<Loop2d> level(shadows.size());
    Loop2d scratch;
    inclusion_exclusion(
        shadows.size(), [&](std::size_t k) { return std::span<const Point2d>(shadows[k]); }, source, 0, 1.0,
        negligible, level, 0, scratch, [&](const Loop2d& loop, double sign) {
          out.loops_.push_back(loop);
          if (sign < 0) std::reverse(out.loops_.back().begin(), out.loops_.back().end());
        });
    return out;
  }
  if (beyond_ == Beyond::kCgalBooleans) {
    out.loops_ = convex_difference(source, shadows);
    return out;
  }
  // Larger shadows first: the source shrinks fastest, and later shadows mostly miss what is left.
  std::sort(shadows.begin(), shadows.end(),
            [](const Loop2d& a, const Loop2d& b) { return signed_area(a) > signed_area(b); });
  thread_local ConvexPieces cutters, pieces;
  thread_local ConvexScratch scratch;
  cutters.clear();
  for (const Loop2d& shadow : shadows)
    if (shadow.size() >= 3 && signed_area(shadow) > negligible) cutters.add(shadow);
  convex_difference_pieces(source, cutters, negligible, pieces, scratch);
  for (std::size_t i = 0; i < pieces.size(); ++i) out.loops_.emplace_back(pieces[i].begin(), pieces[i].end());
  return out;
}

double ExactVisibility::VisibleRegion::factor_of(const Triangle& part) const {
  // Clip every loop to the part (in the source's plane). A loop that is not convex may come out with
  // edges doubling back along the part's boundary; they cancel in the contour sum, which only depends
  // on the winding number the clipped loop keeps.
  Loop2d corners(3);
  for (int k = 0; k < 3; ++k) corners[k] = {dot(part.v[k] - origin_, e1_), dot(part.v[k] - origin_, e2_)};
  if (signed_area(corners) < 0) std::swap(corners[1], corners[2]);
  double factor = 0;
  std::vector<Point3> loop3;
  for (const Loop2d& loop : loops_) {
    const Loop2d clipped = clip_convex(loop, corners);
    if (clipped.size() < 3) continue;
    loop3.clear();
    for (const Point2d& y : clipped) loop3.push_back(origin_ + e1_ * y[0] + e2_ * y[1]);
    factor += point_boundary_factor(p_, n_, loop3);
  }
  return std::max(0.0, factor);
}

double ExactVisibility::hidden_factor(const Point3& p, const Vector3& n, const Triangle& source) const {
  return hidden_among(p, n, source, nullptr, nullptr);
}

double ExactVisibility::hidden_factor(const Point3& p, const Vector3& n, const Triangle& source,
                                      std::span<const int> candidates) const {
  return hidden_among(p, n, source, &candidates, nullptr);
}

double ExactVisibility::hidden_among(const Point3& p_world, const Vector3& n, const Triangle& source_world,
                                     const std::span<const int>* candidates, double* visible) const {
  const Vector3 shift = to_vector(impl_->centre);
  Frame f;
  if (!make_frame(p_world - shift, n, shifted(source_world, shift), f)) return 0;
  std::array<HalfSpace, 5> cone;
  const std::span<const HalfSpace> cone_span(cone.data(), make_cone(f, cone));
  int group = kNoGroup;  // the convex solid of the parts so far, or −2 − k for occluder k alone
  bool several = false;
  double hidden = 0;
  thread_local ClipBuffers buffers;
  auto visit = [&](int k) {
    if (impl_->verdict(k, f.p, f.S, f.region) < 0) return false;
    const std::span<const Point3> part = clip_to_region(impl_->triangles[k], cone_span, buffers);
    if (part.size() < 3) return false;
    const double factor = std::abs(point_boundary_factor(f.p, n, part));
    if (!(factor > 0)) return false;
    const int g = impl_->group(k, f.p, f.S);
    if (group != kNoGroup && g != group) return several = true;
    group = g;
    hidden += factor;
    return false;
  };
  if (candidates == nullptr) {
    impl_->query(f.region, visit);
  } else {
    for (const int k : *candidates)
      if (visit(k)) break;
  }
  if (group == kNoGroup) return 0;
  occluded_.fetch_add(1, std::memory_order_relaxed);
  if (!several) return hidden;
  const double seen = visible_region(p_world, n, source_world, false).factor_of(source_world);
  if (visible != nullptr) *visible = seen;
  return std::max(0.0, point_triangle_factor(p_world, n, source_world) - seen);
}

double ExactVisibility::visible_factor(const Point3& p, const Vector3& n, const Triangle& source) const {
  double visible = -1;  // set where the shadows had to be united
  const double hidden = hidden_among(p, n, source, nullptr, &visible);
  if (visible >= 0) return visible;
  const double whole = point_triangle_factor(p, n, source);
  return hidden > 0 ? std::max(0.0, whole - hidden) : whole;
}

void ExactVisibility::shadow(const Point3& p_world, const Vector3& n, const Triangle& carrier_world,
                             std::span<const int> candidates, Shadow& out) const {
  out.pieces_.clear();
  out.bounds_.clear();
  const Vector3 shift = to_vector(impl_->centre);
  Frame f;
  if (!make_frame(p_world - shift, n, shifted(carrier_world, shift), f)) return;  // no part of it is seen
  std::array<HalfSpace, 5> cone;
  const std::span<const HalfSpace> cone_span(cone.data(), make_cone(f, cone));
  const Point3& s0 = f.S.v[0];
  out.origin_ = carrier_world.v[0];
  out.n_ = n;
  out.e1_ = normalize(f.S.v[1] - s0);
  out.e2_ = cross(f.ns, out.e1_);
  out.to_origin_ = s0 - f.p;
  // The projected parts' corners, by group.
  thread_local std::vector<std::vector<Point2d>> points;
  thread_local std::vector<int> group_of;
  group_of.clear();
  thread_local ClipBuffers buffers;
  for (const int k : candidates) {
    if (impl_->verdict(k, f.p, f.S, f.region) < 0) continue;
    const std::span<const Point3> part = clip_to_region(impl_->triangles[k], cone_span, buffers);
    if (part.size() < 3) continue;
    // A part of no area (an occluder touching the cone's boundary) hides nothing.
    Vector3 twice_area;
    double extent = 0;  // the longest edge, squared
    for (std::size_t i = 0; i < part.size(); ++i) {
      extent = std::max(extent, length_squared(part[(i + 1) % part.size()] - part[i]));
      if (i >= 1 && i + 1 < part.size()) twice_area = twice_area + cross(part[i] - part[0], part[i + 1] - part[0]);
    }
    if (!(length(twice_area) > 1e-12 * extent)) continue;
    const int g = impl_->group(k, f.p, f.S);
    // The candidates of one convex solid are mostly consecutive: look back from the last group.
    std::size_t slot = group_of.size();
    while (slot > 0 && group_of[slot - 1] != g) --slot;
    if (slot == 0) {
      slot = group_of.size();
      group_of.push_back(g);
      if (points.size() <= slot) points.resize(slot + 1);
      points[slot].clear();
    } else {
      --slot;
    }
    for (const Point3& q : part) {
      const Point3 y = f.p + (q - f.p) * (f.h / (f.h - dot(f.ns, q - s0)));
      points[slot].push_back({dot(y - s0, out.e1_), dot(y - s0, out.e2_)});
    }
  }
  if (group_of.empty()) return;
  occluded_.fetch_add(1, std::memory_order_relaxed);
  // Each group's shadow is the convex hull of its parts' projections. Several groups' shadows may
  // overlap: they are united once here, as disjoint convex pieces (larger shadows first, so that
  // smaller ones inside them vanish whole), and each source then sums its parts of the pieces.
  thread_local std::vector<Point2d> hull;
  thread_local ConvexPieces hulls, sorted, united;
  thread_local std::vector<Point2d> piece;
  thread_local std::vector<std::pair<double, int>> by_area;
  thread_local ConvexScratch scratch;
  hulls.clear();
  by_area.clear();
  for (std::size_t slot = 0; slot < group_of.size(); ++slot) {
    convex_hull(points[slot], hull);
    if (hull.size() < 3) continue;
    by_area.emplace_back(-signed_area(hull), static_cast<int>(hulls.size()));
    hulls.add(hull);
  }
  if (hulls.size() > 1) {
    std::sort(by_area.begin(), by_area.end());
    sorted.clear();
    for (const auto& [area, i] : by_area) sorted.add(hulls[static_cast<std::size_t>(i)]);
    // The pieces' edges clip the sources (hidden_factor): corners that a cut through a hull's corner
    // left nearly coincident would give an edge of no direction, which cut them at random.
    convex_union_pieces(sorted, 1e-15 * carrier_world.area(), united, scratch);
    out.pieces_.clear();
    for (std::size_t i = 0; i < united.size(); ++i) {
      piece.assign(united[i].begin(), united[i].end());
      tidy_convex(piece);
      if (!piece.empty()) out.pieces_.add(piece);
    }
  } else {
    out.pieces_ = hulls;
  }
  for (std::size_t i = 0; i < out.pieces_.size(); ++i) {
    Shadow::Bounds b{{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()},
                     {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}};
    for (const Point2d& y : out.pieces_[i])
      for (int a = 0; a < 2; ++a) b.lo[a] = std::min(b.lo[a], y[a]), b.hi[a] = std::max(b.hi[a], y[a]);
    out.bounds_.push_back(b);
  }
}

double ExactVisibility::Shadow::hidden_factor(const Triangle& part) const {
  const std::size_t count = bounds_.size();
  if (count == 0) return 0;
  std::array<Point2d, 3> c;
  Point2d lo = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Point2d hi = {-lo[0], -lo[1]};
  for (int k = 0; k < 3; ++k) {
    const Vector3 d = part.v[k] - origin_;
    c[k] = {dot(d, e1_), dot(d, e2_)};
    for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], c[k][a]), hi[a] = std::max(hi[a], c[k][a]);
  }
  if (cross2(c[0], c[1], c[2]) < 0) std::swap(c[1], c[2]);
  // The contour sum over a loop, each vertex relative to p.
  const auto factor = [&](std::span<const Point2d> loop) {
    thread_local std::vector<Point3> points;
    points.clear();
    for (const Point2d& y : loop) points.push_back(Point3{} + (to_origin_ + e1_ * y[0] + e2_ * y[1]));
    return std::abs(point_boundary_factor(Point3{}, n_, points));
  };
  // Each piece cut to the part; the pieces are disjoint, so their parts' factors add up. The part's
  // corners against the piece's edges first: outside one edge, all three, and the part lies beyond
  // it; inside every edge, and it is all hidden (convex: its corners are). Otherwise the part is
  // clipped by the edges that have a corner outside (the others hold all of it): a patch against a
  // larger shadow meets one or two of them, where the shadow clipped by the part's three edges took
  // three passes over all its corners (41 % of the time of a patch across a shadow's edge,
  // tests/kernels_benchmark.cpp).
  thread_local Loop2d loop, scratch;
  constexpr std::size_t kMaxCuttingEdges = 16;  // beyond: the piece clipped by the part
  double hidden = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const Bounds& b = bounds_[i];
    if (lo[0] >= b.hi[0] || hi[0] <= b.lo[0] || lo[1] >= b.hi[1] || hi[1] <= b.lo[1]) continue;
    const std::span<const Point2d> polygon = pieces_[i];
    const std::size_t m = polygon.size();
    std::array<int, kMaxCuttingEdges> cutting;
    std::size_t cuts = 0;
    bool apart = false, many = false;
    for (std::size_t v = 0; v < m && !apart; ++v) {
      const Point2d& a = polygon[v];
      const Point2d& b = polygon[v + 1 < m ? v + 1 : 0];
      const int outside = (cross2(a, b, c[0]) < 0) + (cross2(a, b, c[1]) < 0) + (cross2(a, b, c[2]) < 0);
      apart = outside == 3;
      if (outside == 0) continue;
      if (cuts < cutting.size()) cutting[cuts] = static_cast<int>(v);
      many = many || cuts == cutting.size();
      ++cuts;
    }
    if (apart) continue;
    if (cuts == 0) return std::numeric_limits<double>::infinity();
    if (many) {
      clip_convex_into(polygon, c, loop, scratch);
    } else {
      if (loop.size() < 3) loop.resize(3);
      std::copy(c.begin(), c.end(), loop.begin());
      std::size_t n = 3;
      for (std::size_t k = 0; k < cuts && n >= 3; ++k) {
        const std::size_t v = static_cast<std::size_t>(cutting[k]);
        n = clip_pass(loop, n, polygon[v], polygon[v + 1 < m ? v + 1 : 0], scratch);
      }
      loop.resize(n);
    }
    if (loop.size() >= 3) hidden += factor(loop);
  }
  return hidden;
}

}  // namespace lambert
