// Exact partial visibility by central projection and exact 2D Boolean operations; see
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
// rounding; the Boolean difference with S then cuts at S's edges exactly.
//
// The projections are subtracted from S (clipped at p's horizon) by mesh/polygon_boolean.h (CGAL
// Polygon_set_2, exact constructions), and the visible factor is the signed contour sum over the
// outer boundaries (counter-clockwise) and holes (clockwise) of the result.
#include "solver/exact_visibility.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <vector>

#include "mesh/polygon_boolean.h"
#include "solver/form_factor.h"

namespace lambert {
namespace {

// A half-space {x : dot(normal, x − origin) >= offset}.
struct HalfSpace {
  Vector3 normal;
  Point3 origin;
  double offset = 0;
  double signed_distance(const Point3& x) const { return dot(normal, x - origin) - offset; }
};

// A small convex polygon in 3D: a triangle clipped by k planes has at most 3 + k vertices (k is 6
// for a projection's region, at most 2·16 − 4 = 28 for a shaft's hull faces).
struct SmallPolygon {
  std::array<Point3, 32> v;
  int count = 0;
};

SmallPolygon clip(const SmallPolygon& in, const HalfSpace& h) {
  SmallPolygon out;
  for (int i = 0; i < in.count; ++i) {
    const Point3& a = in.v[i];
    const Point3& b = in.v[(i + 1) % in.count];
    const double da = h.signed_distance(a), db = h.signed_distance(b);
    if (da >= 0 && out.count < static_cast<int>(out.v.size())) out.v[out.count++] = a;
    if ((da >= 0) != (db >= 0) && out.count < static_cast<int>(out.v.size())) {
      const double t = da / (da - db);
      out.v[out.count++] = a + (b - a) * t;
    }
  }
  return out;
}

// The part of a triangle inside every half-space of a region (fewer than 3 vertices: none).
SmallPolygon clip_to_region(const Triangle& t, std::span<const HalfSpace> region) {
  SmallPolygon part;
  part.count = 3;
  std::copy(t.v.begin(), t.v.end(), part.v.begin());
  for (const HalfSpace& r : region) {
    part = clip(part, r);
    if (part.count < 3) break;
  }
  return part;
}

double signed_area(const Loop2d& loop) {
  double a = 0;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    const Point2d& u = loop[i];
    const Point2d& w = loop[(i + 1) % n];
    a += u[0] * w[1] - w[0] * u[1];
  }
  return 0.5 * a;
}

// The part of `subject` inside convex counter-clockwise `clip` (Sutherland–Hodgman, doubles). The
// subject keeps its orientation; a subject that is not convex may come out with edges doubling back
// along the clip's boundary, which cancel in a contour sum.
Loop2d clip_convex(const Loop2d& subject, const Loop2d& clip) {
  Loop2d out = subject;
  for (std::size_t e = 0, m = clip.size(); e < m && out.size() >= 3; ++e) {
    const Point2d& a = clip[e];
    const Point2d& b = clip[(e + 1) % m];
    auto side = [&](const Point2d& q) { return (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0]); };
    Loop2d next;
    for (std::size_t i = 0, n = out.size(); i < n; ++i) {
      const Point2d& u = out[i];
      const Point2d& w = out[(i + 1) % n];
      const double su = side(u), sw = side(w);
      if (su >= 0) next.push_back(u);
      if ((su >= 0) != (sw >= 0)) {
        const double t = su / (su - sw);
        next.push_back({u[0] + (w[0] - u[0]) * t, u[1] + (w[1] - u[1]) * t});
      }
    }
    out = std::move(next);
  }
  return out;
}

// S minus the union of a few convex shadows as signed convex loops, by inclusion–exclusion:
// ∫_{S∖∪A_k} = Σ over subsets K of (−1)^|K| ∫_{S∩A_K}. Each intersection is convex (clipped in
// doubles); negative terms are stored clockwise, so the contour sum subtracts them. Subsets whose
// intersection is empty (area below `negligible`) are pruned with all their supersets.
void inclusion_exclusion(const Loop2d& current, std::size_t next, bool positive, std::span<const Loop2d> shadows,
                         double negligible, std::vector<Loop2d>& loops) {
  loops.push_back(current);
  if (!positive) std::reverse(loops.back().begin(), loops.back().end());
  for (std::size_t k = next; k < shadows.size(); ++k) {
    const Loop2d part = clip_convex(current, shadows[k]);
    if (part.size() < 3 || std::abs(signed_area(part)) <= negligible) continue;
    inclusion_exclusion(part, k + 1, !positive, shadows, negligible, loops);
  }
}

// Whether a box lies wholly outside the half-space (its farthest corner along the normal is outside).
bool box_outside(const Bounds3& box, const HalfSpace& h) {
  const Point3 far{h.normal.x >= 0 ? box.hi.x : box.lo.x, h.normal.y >= 0 ? box.hi.y : box.lo.y,
                   h.normal.z >= 0 ? box.hi.z : box.lo.z};
  return h.signed_distance(far) < 0;
}

}  // namespace

// Bounding-volume hierarchy over the occluders (median split on the longest axis of the centroids'
// box, leaves of up to 4 triangles), queried with the convex region that can occlude.
struct ExactVisibility::Impl {
  struct Node {
    Bounds3 box;
    int first = 0, count = 0;  // leaf: triangles [first, first + count) of `order`
    int right = -1;            // inner node: left child is the next node
  };
  Point3 centre;                   // occluders are stored relative to it (geo-referenced scenes)
  std::vector<Triangle> triangles;
  std::vector<char> outward_solid;  // per triangle (see the constructor)
  std::vector<int> order;
  std::vector<Node> nodes;

  int build(int first, int count, std::vector<Point3>& centroids) {
    const int index = static_cast<int>(nodes.size());
    nodes.emplace_back();
    Bounds3 box, centroid_box;
    for (int k = first; k < first + count; ++k) {
      for (const Point3& v : triangles[order[k]].v) box.add(v);
      centroid_box.add(centroids[order[k]]);
    }
    nodes[index].box = box;
    if (count <= 4) {
      nodes[index].first = first;
      nodes[index].count = count;
      return index;
    }
    const Vector3 d = centroid_box.diagonal();
    const int axis = d.x >= d.y && d.x >= d.z ? 0 : (d.y >= d.z ? 1 : 2);
    const int half = count / 2;
    std::nth_element(order.begin() + first, order.begin() + first + half, order.begin() + first + count,
                     [&](int a, int b) { return centroids[a][axis] < centroids[b][axis]; });
    build(first, half, centroids);
    const int right = build(first + half, count - half, centroids);
    nodes[index].right = right;
    return index;
  }

  // Calls visit(triangle, outward_solid) for the triangles in leaves whose boxes meet the region,
  // until it returns true; returns whether one did.
  template <class Visit>
  bool query(std::span<const HalfSpace> region, Visit&& visit) const {
    if (nodes.empty()) return false;
    thread_local std::vector<int> stack;  // reused: one allocation per thread, not per query
    stack.assign(1, 0);
    while (!stack.empty()) {
      const Node& node = nodes[stack.back()];
      const int index = stack.back();
      stack.pop_back();
      if (std::any_of(region.begin(), region.end(), [&](const HalfSpace& h) { return box_outside(node.box, h); }))
        continue;
      if (node.right < 0) {
        for (int k = node.first; k < node.first + node.count; ++k)
          if (visit(triangles[order[k]], outward_solid[order[k]] != 0)) return true;
      } else {
        stack.push_back(node.right);
        stack.push_back(index + 1);
      }
    }
    return false;
  }
};

ExactVisibility::ExactVisibility(std::span<const Triangle> occluders, std::span<const char> outward_solid)
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
    impl_->outward_solid.push_back(k < outward_solid.size() ? outward_solid[k] : 0);
    centroids.push_back(local.centroid());
  }
  impl_->order.resize(impl_->triangles.size());
  std::iota(impl_->order.begin(), impl_->order.end(), 0);
  if (!impl_->triangles.empty()) impl_->build(0, static_cast<int>(impl_->triangles.size()), centroids);
}

ExactVisibility::~ExactVisibility() = default;

ExactVisibility::VisibleRegion ExactVisibility::visible_region(const Point3& p_world, const Vector3& n,
                                                              const Triangle& source_world) const {
  VisibleRegion out;
  const Vector3 shift = to_vector(impl_->centre);
  const Point3 p = p_world - shift;
  const Triangle S{{source_world.v[0] - shift, source_world.v[1] - shift, source_world.v[2] - shift}};
  const Vector3 area_vector = S.area_vector();
  if (!(length(area_vector) > 0)) return out;
  const Vector3 ns = normalize(area_vector);
  const Point3& s0 = S.v[0];
  const double h = dot(ns, p - s0);
  if (!(h > 0)) return out;  // p behind or in the source's plane: the source's front does not face it
  const Point3 c = S.centroid();
  const double scale = distance(p, c) + S.bounding_radius();

  // The part of S in front of p's horizon.
  const HalfSpace horizon{n, p, 1e-12 * scale};
  SmallPolygon front;
  front.count = 3;
  std::copy(S.v.begin(), S.v.end(), front.v.begin());
  front = clip(front, HalfSpace{n, p, 0});
  if (front.count < 3) return out;

  // Region that can occlude: the cone from p over S enlarged by 5 %, above S's plane (by a margin
  // relative to h: occluders in S's own plane, i.e. S's surface and its coplanar neighbours, do not
  // occlude), in front of p's horizon, below p's height.
  std::array<HalfSpace, 6> region;
  for (int e = 0; e < 3; ++e) {
    const Point3 a = c + (S.v[e] - c) * 1.05, b = c + (S.v[(e + 1) % 3] - c) * 1.05;
    Vector3 m = cross(a - p, b - p);
    if (dot(m, c - p) < 0) m = -m;
    region[e] = HalfSpace{m, p, 0};
  }
  region[3] = HalfSpace{ns, s0, 1e-9 * h};
  region[4] = horizon;
  region[5] = HalfSpace{-ns, s0, -h * (1 - 1e-12)};

  out.p_ = p_world;
  out.n_ = n;
  out.origin_ = source_world.v[0];
  out.e1_ = normalize(S.v[1] - s0);
  out.e2_ = cross(ns, out.e1_);
  auto to_plane = [&](const Point3& y) { return Point2d{dot(y - s0, out.e1_), dot(y - s0, out.e2_)}; };
  std::vector<Loop2d> shadows;
  impl_->query(region, [&](const Triangle& t, bool outward_solid) {
    if (outward_solid && dot(t.area_vector(), p - t.v[0]) <= 0) return false;  // a solid's face seen from behind
    // The corners decide for most triangles, as in shaft_is_clear: wholly outside one half-space (no
    // shadow) or inside all of them (the whole triangle); only the rest are clipped.
    bool inside = true;
    for (const HalfSpace& r : region) {
      const double d0 = r.signed_distance(t.v[0]), d1 = r.signed_distance(t.v[1]), d2 = r.signed_distance(t.v[2]);
      if (d0 < 0 && d1 < 0 && d2 < 0) return false;
      inside = inside && d0 >= 0 && d1 >= 0 && d2 >= 0;
    }
    SmallPolygon part;
    if (inside) {
      part.count = 3;
      std::copy(t.v.begin(), t.v.end(), part.v.begin());
    } else {
      part = clip_to_region(t, region);
    }
    if (part.count < 3) return false;
    Loop2d shadow(part.count);
    for (int k = 0; k < part.count; ++k) {
      const Point3& q = part.v[k];
      shadow[k] = to_plane(p + (q - p) * (h / (h - dot(ns, q - s0))));
    }
    shadows.push_back(std::move(shadow));
    return false;
  });

  Loop2d source(front.count);
  for (int k = 0; k < front.count; ++k) source[k] = to_plane(front.v[k]);
  if (shadows.empty()) {
    out.loops_.push_back(std::move(source));
    return out;
  }
  booleans_.fetch_add(1, std::memory_order_relaxed);
  // A few shadows (the usual case: a box seen from a point casts two to six): inclusion–exclusion over
  // convex intersections in doubles, with no Boolean operation; many: CGAL's exact difference, whose
  // cost does not grow as 2^k.
  if (shadows.size() <= static_cast<std::size_t>(inclusion_exclusion_limit_)) {
    for (Loop2d& shadow : shadows)
      if (signed_area(shadow) < 0) std::reverse(shadow.begin(), shadow.end());
    inclusion_exclusion(source, 0, true, shadows, 1e-15 * std::abs(signed_area(source)), out.loops_);
    return out;
  }
  out.loops_ = convex_difference(source, shadows);
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

double ExactVisibility::visible_factor(const Point3& p, const Vector3& n, const Triangle& source) const {
  return visible_region(p, n, source).factor_of(source);
}

bool ExactVisibility::shaft_is_clear(std::span<const Point3> points_world) const {
  const Vector3 shift = to_vector(impl_->centre);
  std::array<Point3, 16> p;
  const int n = static_cast<int>(std::min<std::size_t>(points_world.size(), p.size()));
  Bounds3 box;
  for (int i = 0; i < n; ++i) box.add(p[i] = points_world[i] - shift);
  const double size = length(box.diagonal());
  if (!(size > 0)) return true;
  const double margin = 1e-9 * size;
  // Faces of the hull: planes through three points with every point on one side (brute force; a
  // shaft has at most 16 points). Normals point inwards; the region is the hull shrunk by `margin`.
  std::vector<HalfSpace> region;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      for (int k = j + 1; k < n; ++k) {
        Vector3 normal = cross(p[j] - p[i], p[k] - p[i]);
        const double len = length(normal);
        if (!(len > 1e-12 * size * size)) continue;
        normal = normal / len;
        int above = 0, below = 0;
        for (int m = 0; m < n; ++m) {
          const double d = dot(normal, p[m] - p[i]);
          above += d > margin;
          below += d < -margin;
        }
        if (above > 0 && below > 0) continue;
        if (above == 0 && below == 0) continue;  // every point in this plane
        const HalfSpace face{above > 0 ? normal : -normal, p[i], margin};
        const bool known = std::any_of(region.begin(), region.end(), [&](const HalfSpace& h) {
          return dot(h.normal, face.normal) > 1 - 1e-12 && std::abs(h.signed_distance(p[i]) + margin) <= margin;
        });
        if (!known) region.push_back(face);
      }
  if (region.empty()) return true;  // flat: nothing can be inside
  // Most triangles that the tree hands over lie wholly outside one face of the hull or wholly inside
  // every face: their corners decide, as clip_to_region would (an empty part, or the whole triangle),
  // and only triangles that cross a face are clipped.
  auto meets_region = [&](const Triangle& t, bool) {
    bool inside = true;
    for (const HalfSpace& h : region) {
      const double d0 = h.signed_distance(t.v[0]), d1 = h.signed_distance(t.v[1]), d2 = h.signed_distance(t.v[2]);
      if (d0 < 0 && d1 < 0 && d2 < 0) return false;
      inside = inside && d0 >= 0 && d1 >= 0 && d2 >= 0;
    }
    return inside || clip_to_region(t, region).count >= 3;
  };
  return !impl_->query(region, meets_region);
}

}  // namespace lambert
