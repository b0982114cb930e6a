// Closed surfaces (see solids.h).
#include "solver/solids.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>

#include "solver/radiosity.h"

namespace lambert {
namespace {

// The components of the scene's triangles and, per component, what tells whether it is closed.
struct Components {
  std::vector<Triangle> triangles;  // every surface's, in order
  std::vector<int> corner;     // corner 3 t + k → its welded position
  std::vector<int> owner;      // surface of each triangle
  std::vector<int> component;  // of each triangle: the index of its component's first triangle
  struct Sums {
    Vector3 vector_area{};
    double area = 0, volume = 0;  // volume: signed, positive where the faces point out of it
    bool consistent = true;       // every shared edge runs opposite ways in its two triangles
    bool holed = false;           // an edge of one triangle that no other one runs back along
  };
  std::vector<Sums> sums;      // per component (indexed as `component`)
  Point3 origin;               // of the volumes
  // Edges with one triangle: that triangle, the edge's ends (welded positions, lower first) and
  // whether it runs from a to b there.
  struct BoundaryEdge {
    int triangle, a, b;
    bool forward;
  };
  std::vector<BoundaryEdge> boundary;
  bool closed(int c) const {
    const Sums& s = sums[c];
    return s.area > 0 && !s.holed && length(s.vector_area) <= 1e-6 * s.area &&
           std::abs(s.volume) > 1e-6 * s.area * std::sqrt(s.area);
  }
};

Components components(const std::vector<Surface>& surfaces) {
  Components out;
  std::vector<Triangle>& all = out.triangles;
  std::vector<Point3> corners;
  for (std::size_t s = 0; s < surfaces.size(); ++s)
    for (std::size_t t = 0; t < surfaces[s].mesh.triangles.size(); ++t) {
      all.push_back(surfaces[s].mesh.triangle(t)), out.owner.push_back(static_cast<int>(s));
      for (const Point3& p : all.back().v) corners.push_back(p);
    }
  out.corner = weld_identical_positions(corners);
  const std::vector<int>& vertex = out.corner;
  std::vector<int> parent(all.size());  // union–find over the triangles
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  const std::vector<EdgeUse> uses = sorted_edge_uses(all.size(), [&](std::size_t t) {
    return std::array<int, 3>{vertex[3 * t], vertex[3 * t + 1], vertex[3 * t + 2]};
  });
  // Triangles are joined across edges that exactly two of them share. An edge shared by more (a crate's
  // wall standing on a floor whose triangles meet below it, two cubes touching along an edge) joins
  // nothing: each component then sees its own uses of it below.
  for_each_edge(uses, [&](std::span<const EdgeUse> edge) {
    if (edge.size() == 2) parent[root(edge[1].triangle)] = root(edge[0].triangle);
  });
  // Per edge and component: one use is an edge of its boundary; two must run opposite ways; more are
  // inconsistent.
  std::vector<char> inconsistent(all.size(), 0);
  std::vector<std::pair<int, const EdgeUse*>> by_component;
  for_each_edge(uses, [&](std::span<const EdgeUse> edge) {
    by_component.clear();
    for (const EdgeUse& u : edge) by_component.emplace_back(root(u.triangle), &u);
    std::sort(by_component.begin(), by_component.end(),
              [](const auto& x, const auto& y) { return x.first < y.first; });
    for (std::size_t u = 0, v; u < by_component.size(); u = v) {
      for (v = u + 1; v < by_component.size() && by_component[v].first == by_component[u].first; ++v) {
      }
      const EdgeUse& first = *by_component[u].second;
      if (v - u == 1) {
        out.boundary.push_back({first.triangle, first.lo, first.hi, first.forward});
      } else if (v - u > 2 || by_component[u + 1].second->forward == first.forward) {
        for (std::size_t w = u; w < v; ++w) inconsistent[by_component[w].second->triangle] = 1;
      }
    }
  });
  out.component.resize(all.size());
  out.sums.resize(all.size());
  const Point3 o = out.origin = all.empty() ? Point3{} : all[0].v[0];
  for (std::size_t t = 0; t < all.size(); ++t) {
    const int c = out.component[t] = root(static_cast<int>(t));
    Components::Sums& s = out.sums[c];
    const Vector3 a = all[t].v[0] - o, b = all[t].v[1] - o, d = all[t].v[2] - o;
    const Vector3 twice = cross(b - a, d - a);
    s.vector_area = s.vector_area + twice * 0.5;
    s.area += 0.5 * length(twice);
    s.volume += dot(a, cross(b, d)) / 6;
    s.consistent = s.consistent && !inconsistent[t];
  }
  // A closed surface may have edges of one triangle where its meshes meet at T-junctions, but then
  // other such edges run back along each of them. An edge where no other one of its component runs
  // back over a point of it borders a hole, which the vector area does not see where holes face
  // each other (a cube missing one floor and one roof triangle). Components with more than
  // kMaxCheckedBoundary such edges are not checked (sparse: most components have none).
  constexpr std::size_t kMaxCheckedBoundary = 4096;
  std::map<int, std::vector<const Components::BoundaryEdge*>> edges_of;
  for (const auto& e : out.boundary) edges_of[out.component[e.triangle]].push_back(&e);
  auto position = [&](int v) { return all[v / 3].v[v % 3]; };
  for (const auto& [k, edges] : edges_of) {
    if (edges.size() > kMaxCheckedBoundary) continue;
    for (const Components::BoundaryEdge* e : edges) {
      if (e->a == e->b) continue;  // a degenerate triangle's edge of no length
      const Point3 p = position(e->forward ? e->a : e->b), q = position(e->forward ? e->b : e->a);
      const Point3 m = p + (q - p) * 0.41421356;  // not where a junction usually lies (its midpoint)
      const bool covered = std::any_of(edges.begin(), edges.end(), [&](const Components::BoundaryEdge* f) {
        if (f == e) return false;
        const Point3 r = position(f->forward ? f->a : f->b), t = position(f->forward ? f->b : f->a);
        const Vector3 d = t - r;
        if (!(dot(d, q - p) < 0)) return false;  // runs back
        const double l2 = dot(d, d), u = dot(m - r, d) / l2;
        return u > 0 && u < 1 && length(m - (r + d * u)) <= 1e-9 * std::sqrt(l2);
      });
      if (!covered) {
        out.sums[k].holed = true;
        break;
      }
    }
  }
  return out;
}

// Whether a closed solid of triangles `faces` (of c) is convex, by local tests that cost O(faces): every
// edge has exactly one triangle running back along it, whose third corner lies on or behind this
// triangle's plane (the dihedral angle is at most π); the angles at each corner sum to at most 2π;
// and V − E + F = 2. Such a surface is locally convex and its Gauss map covers the sphere once, so by
// Hadamard's theorem it bounds a convex body. (A sphere of 20 480 facets would need 2 × 10⁸ corner–face
// checks the global way.) False where the mesh is not such a manifold (T-junctions, say): unknown.
bool locally_convex(const Components& c, const std::vector<int>& faces, double tolerance) {
  struct Directed {
    int a, b, triangle, third;
    bool operator<(const Directed& o) const { return a != o.a ? a < o.a : b < o.b; }
  };
  std::vector<Directed> edges;
  edges.reserve(3 * faces.size());
  std::vector<std::pair<int, double>> angles;  // (corner, angle there)
  angles.reserve(3 * faces.size());
  for (int t : faces) {
    const Triangle& f = c.triangles[t];
    if (!(length(f.area_vector()) > 0)) return false;  // no plane to be behind
    for (int k = 0; k < 3; ++k) {
      if (c.corner[3 * t + k] < 0) return false;  // not finite (weld_identical_positions)
      edges.push_back({c.corner[3 * t + k], c.corner[3 * t + (k + 1) % 3], t, c.corner[3 * t + (k + 2) % 3]});
      const Vector3 u = f.v[(k + 1) % 3] - f.v[k], w = f.v[(k + 2) % 3] - f.v[k];
      const double lu = length(u), lw = length(w);
      if (!(lu > 0 && lw > 0)) return false;
      angles.emplace_back(c.corner[3 * t + k], std::acos(std::clamp(dot(u, w) / (lu * lw), -1.0, 1.0)));
    }
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const Directed& e = edges[i];
    if (i + 1 < edges.size() && !(e < edges[i + 1])) return false;  // the same directed edge twice
    const auto back = std::lower_bound(edges.begin(), edges.end(), Directed{e.b, e.a, 0, 0});
    if (back == edges.end() || back->a != e.b || back->b != e.a) return false;
    if (back + 1 != edges.end() && !(*back < *(back + 1))) return false;
    const Triangle& f = c.triangles[e.triangle];
    int k = 0;  // the corner of the triangle across the edge that is not on it
    while (k < 2 && c.corner[3 * back->triangle + k] != back->third) ++k;
    if (dot(normalize(f.area_vector()), c.triangles[back->triangle].v[k] - f.v[0]) > tolerance) return false;
  }
  std::sort(angles.begin(), angles.end());
  std::size_t vertices = 0;
  for (std::size_t i = 0, j; i < angles.size(); i = j) {
    double sum = 0;
    for (j = i; j < angles.size() && angles[j].first == angles[i].first; ++j) sum += angles[j].second;
    if (sum > 2 * std::numbers::pi + 1e-9) return false;
    ++vertices;
  }
  const std::ptrdiff_t euler = static_cast<std::ptrdiff_t>(vertices) - static_cast<std::ptrdiff_t>(edges.size() / 2) +
                               static_cast<std::ptrdiff_t>(faces.size());
  return euler == 2;
}

}  // namespace

std::vector<char> surfaces_bounding_solids(const std::vector<Surface>& surfaces) {
  const Components c = components(surfaces);
  std::vector<char> solid(surfaces.size(), 0);
  for (std::size_t t = 0; t < c.component.size(); ++t)
    if (c.closed(c.component[t])) solid[c.owner[t]] = 1;
  return solid;
}

OutwardSolids outward_solids(const std::vector<Surface>& surfaces) {
  const Components c = components(surfaces);
  OutwardSolids out;
  out.solid.assign(c.component.size(), -1);
  const std::size_t T = c.component.size();
  // Open components that a plane would close (see OutwardSolids::cap): every edge with one
  // triangle lies in one plane, whose outward normal is minus the component's vector area.
  // Per component with edges of one triangle: their ends (most components have none: sparse).
  std::map<int, std::vector<int>> boundary;
  for (const auto& e : c.boundary) {
    auto& ends = boundary[c.component[e.triangle]];
    ends.push_back(e.a), ends.push_back(e.b);
  }
  auto position = [&](int v) { return c.triangles[v / 3].v[v % 3]; };
  OutwardSolids::Cap cap_found;  // capped(k)'s, where it returns true
  auto capped = [&](int k) {
    const Components::Sums& s = c.sums[k];
    const auto it = boundary.find(k);
    if (it == boundary.end() || !s.consistent || !(s.area > 0)) return false;
    const std::vector<int>& ends = it->second;
    const double cap_area = length(s.vector_area);
    if (!(cap_area > 1e-6 * s.area)) return false;
    const Vector3 m = s.vector_area / -cap_area;
    const Point3 q0 = position(ends[0]);
    Bounds3 box;
    for (int v : ends) box.add(position(v));
    const double tolerance = 1e-9 * std::max(length(box.diagonal()), std::sqrt(s.area));
    for (int v : ends)
      if (std::abs(dot(m, position(v) - q0)) > tolerance) return false;
    // The volume the faces and the cap enclose: the cap's part is (q0 − o) · A_cap / 3.
    const double volume = s.volume + dot(q0 - c.origin, m * cap_area) / 3;
    const double area = s.area + cap_area;
    if (!(volume > 1e-6 * area * std::sqrt(area))) return false;
    cap_found = {true, m, q0};
    return true;
  };
  std::vector<int> index(T, -1);       // component → solid
  std::vector<char> decided(T, 0), is_solid(T, 0);
  std::vector<std::vector<int>> faces;  // per solid: its triangles
  for (std::size_t t = 0; t < T; ++t) {
    const int k = c.component[t];
    if (!decided[k]) {
      decided[k] = 1;
      cap_found = {};
      is_solid[k] = (c.closed(k) && c.sums[k].consistent && c.sums[k].volume > 0) || capped(k);
      if (is_solid[k]) {
        index[k] = static_cast<int>(faces.size()), faces.emplace_back();
        out.cap.push_back(cap_found);
      }
    }
    if (!is_solid[k]) continue;
    out.solid[t] = index[k];
    faces[index[k]].push_back(static_cast<int>(t));
  }
  out.convex.assign(faces.size(), 0);
  double budget = OutwardSolids::kMaxConvexityChecks;  // corner–face pairs, over all solids
  for (std::size_t s = 0; s < faces.size(); ++s) {
    std::vector<int> corners;
    for (int t : faces[s])
      for (int k = 0; k < 3; ++k) corners.push_back(c.corner[3 * t + k]);
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    std::vector<Point3> points;  // one per welded position (corner 3 t + k has position 3 t + k too)
    Bounds3 box;
    for (int v : corners)
      if (v >= 0) box.add(points.emplace_back(position(v)));
    const double tolerance = 1e-9 * length(box.diagonal());
    const double checks = static_cast<double>(corners.size()) * static_cast<double>(faces[s].size() + 1);
    if (checks > budget) {
      out.convex[s] = !out.cap[s].open && locally_convex(c, faces[s], tolerance);
      continue;
    }
    budget -= checks;
    const auto behind = [&](const Vector3& normal, const Point3& on) {
      return std::all_of(points.begin(), points.end(), [&](const Point3& q) { return dot(normal, q - on) <= tolerance; });
    };
    const auto convex_at = [&](int t) {
      const Triangle& f = c.triangles[t];
      return behind(normalize(f.area_vector()), f.v[0]);
    };
    const OutwardSolids::Cap& cap = out.cap[s];
    out.convex[s] = std::all_of(faces[s].begin(), faces[s].end(), convex_at) && (!cap.open || behind(cap.normal, cap.point));
  }
  // An open component is kept only where convex: ExactVisibility relies on the cap for nothing else.
  std::vector<int> renumber(faces.size(), -1);
  OutwardSolids kept;
  kept.solid.assign(T, -1);
  for (std::size_t s = 0; s < faces.size(); ++s) {
    if (out.cap[s].open && !out.convex[s]) continue;
    renumber[s] = static_cast<int>(kept.convex.size());
    kept.convex.push_back(out.convex[s]);
    kept.cap.push_back(out.cap[s]);
  }
  for (std::size_t t = 0; t < T; ++t)
    if (out.solid[t] >= 0) kept.solid[t] = renumber[out.solid[t]];
  return kept;
}

std::unique_ptr<ExactVisibility> scene_exact_visibility(const Scene& scene) {
  const OutwardSolids solids = outward_solids(scene.surfaces);
  return std::make_unique<ExactVisibility>(input_triangles(scene), solids.solid, solids.convex, solids.cap);
}

}  // namespace lambert
