#include "solver/hierarchical/solid_shafts.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>

namespace lambert::hierarchical {
namespace {

constexpr int kLeafBlockers = 4;
// A pair whose hull meets the bounding spheres of more occluders than this, not its own, is left to
// its rays: each costs a test of its planes, and so many near one pair seldom all keep out of it.
constexpr int kNearBlockers = 8;

// Whether the segment p + t d, t ∈ [0, 1], meets the box grown by `grow` on every side (slab test;
// `inverse`: 1 / d per axis, ±∞ where d is 0; a 0 × ∞ there is NaN, which max and min pass over, so
// that axis then bounds nothing: conservative).
bool segment_meets_box(const Point3& p, const std::array<double, 3>& inverse, const Bounds3& box, double grow) {
  double t0 = 0, t1 = 1;
  for (int a = 0; a < 3; ++a) {
    double enter = (box.lo[a] - grow - p[a]) * inverse[a], leave = (box.hi[a] + grow - p[a]) * inverse[a];
    if (enter > leave) std::swap(enter, leave);
    t0 = std::max(t0, enter);
    t1 = std::min(t1, leave);
    if (t0 > t1) return false;
  }
  return true;
}

Vector3 unit_normal_of(const Triangle& t) {
  const Vector3 n = t.area_vector();
  const double len = length(n);
  return len > 0 ? n / len : Vector3{};
}

// Gives every triangle of no solid (group −1) a group: one per set of triangles in one plane (to
// `tolerance`, facing the same way) joined across shared edges, numbered from `groups` on. Returns
// the number of groups.
int join_coplanar(std::span<const Triangle> inputs, double tolerance, std::vector<int>& group, int groups) {
  const std::size_t K = inputs.size();
  std::vector<int> parent(K);
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::map<std::array<double, 6>, int> edge_owner;  // an edge's ends, lower first → a triangle
  for (std::size_t k = 0; k < K; ++k) {
    if (group[k] >= 0) continue;
    const Vector3 n = unit_normal_of(inputs[k]);
    for (int e = 0; e < 3; ++e) {
      const Point3 &p = inputs[k].v[e], &q = inputs[k].v[(e + 1) % 3];
      const bool p_first = std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
      const Point3 &lo = p_first ? p : q, &hi = p_first ? q : p;
      const auto [it, fresh] = edge_owner.try_emplace({lo.x, lo.y, lo.z, hi.x, hi.y, hi.z}, static_cast<int>(k));
      if (fresh) continue;
      const Triangle& other = inputs[it->second];
      const bool coplanar = std::all_of(other.v.begin(), other.v.end(), [&](const Point3& x) {
        return std::abs(dot(n, x - inputs[k].v[0])) <= tolerance;
      });
      if (coplanar && dot(n, unit_normal_of(other)) > 0) parent[root(static_cast<int>(k))] = root(it->second);
    }
  }
  std::vector<int> of_root(K, -1);
  for (std::size_t k = 0; k < K; ++k) {
    if (group[k] >= 0) continue;
    const int r = root(static_cast<int>(k));
    if (of_root[r] < 0) of_root[r] = groups++;
    group[k] = of_root[r];
  }
  return groups;
}

}  // namespace

SolidShafts::SolidShafts(const ElementForest& forest, const ClusterTree& tree, std::span<const Triangle> inputs,
                         std::span<const int> solid, std::span<const char> convex)
    : forest_(forest), tree_(tree) {
  auto solid_of = [&](std::size_t k) { return k < solid.size() ? solid[k] : -1; };
  auto is_convex = [&](int s) { return s >= 0 && static_cast<std::size_t>(s) < convex.size() && convex[s]; };
  Bounds3 scene;
  for (const Triangle& t : inputs)
    for (const Point3& p : t.v) scene.add(p);
  tolerance_ = 1e-9 * length(scene.diagonal());

  // The groups: one per solid, and one per set of triangles of no solid that are coplanar and joined
  // across shared edges (a floor cut around what stands on it is one plane to test, not hundreds).
  const std::size_t K = inputs.size();
  std::vector<int> group(K, -1);
  int groups = 0;
  std::vector<int> of_solid;
  for (std::size_t k = 0; k < K; ++k) {
    const int s = solid_of(k);
    if (s < 0) continue;
    if (static_cast<std::size_t>(s) >= of_solid.size()) of_solid.resize(s + 1, -1);
    if (of_solid[s] < 0) of_solid[s] = groups++;
    group[k] = of_solid[s];
  }
  const auto loose = static_cast<std::size_t>(std::count(group.begin(), group.end(), -1));
  if (static_cast<std::size_t>(groups) > kMaxBlockers || loose > kMaxLooseTriangles) return;
  groups = join_coplanar(inputs, tolerance_, group, groups);

  // Each group's sphere (about its box's centre) and planes.
  std::vector<Bounds3> box(groups);
  std::vector<int> example(groups, -1);  // a triangle of the group
  for (std::size_t k = 0; k < K; ++k) {
    for (const Point3& p : inputs[k].v) box[group[k]].add(p);
    if (example[group[k]] < 0) example[group[k]] = static_cast<int>(k);
  }
  blockers_.resize(groups);
  for (int g = 0; g < groups; ++g) {
    Blocker& b = blockers_[g];
    b.centre = box[g].center();
    const int s = solid_of(static_cast<std::size_t>(example[g]));
    b.solid = s;
    b.convex = is_convex(s);
    if (s < 0) b.plane = {unit_normal_of(inputs[example[g]]), inputs[example[g]].v[0]};
  }
  std::vector<std::vector<Plane>> faces(groups);  // a convex solid's distinct face planes, up to kFacePlanes + 1
  for (std::size_t k = 0; k < K; ++k) {
    Blocker& b = blockers_[group[k]];
    for (const Point3& p : inputs[k].v) b.radius = std::max(b.radius, distance(p, b.centre));
    std::vector<Plane>& planes = faces[group[k]];
    if (!b.convex || planes.size() > kFacePlanes) continue;
    const Plane plane{unit_normal_of(inputs[k]), inputs[k].v[0]};
    if (!(length_squared(plane.normal) > 0)) {  // a face of no area: the solid keeps its sphere alone,
      planes.resize(kFacePlanes + 1);             // as one of too many planes does
      continue;
    }
    const bool known = std::any_of(planes.begin(), planes.end(), [&](const Plane& q) {
      return dot(q.normal, plane.normal) > 1 - 1e-12 && std::abs(dot(q.normal, plane.on - q.on)) <= tolerance_;
    });
    if (!known) planes.push_back(plane);
  }
  for (int g = 0; g < groups; ++g) {
    if (faces[g].size() > kFacePlanes) continue;  // a faceted sphere: its bounding sphere serves
    blockers_[g].first_face = static_cast<int>(face_planes_.size());
    blockers_[g].face_count = static_cast<int>(faces[g].size());
    face_planes_.insert(face_planes_.end(), faces[g].begin(), faces[g].end());
  }
  if (blockers_.size() > kMaxBlockers) return;
  used_ = true;
  if (!blockers_.empty()) {
    nodes_.reserve(2 * blockers_.size());
    nodes_.emplace_back();
    build(0, 0, static_cast<int>(blockers_.size()));
  }

  element_solid_.resize(forest.elements.size());
  for (std::size_t e = 0; e < forest.elements.size(); ++e) {
    const int s = solid_of(static_cast<std::size_t>(forest.elements[e].input));
    element_solid_[e] = is_convex(s) ? s : -1;
  }
  cluster_solid_.assign(tree.clusters.size(), -1);
  for (std::size_t c = tree.clusters.size(); c-- > 0;) {  // children come after their parent
    const Cluster& C = tree.clusters[c];
    if (C.root >= 0) cluster_solid_[c] = element_solid_[C.root];
    else if (cluster_solid_[C.child[0]] == cluster_solid_[C.child[1]]) cluster_solid_[c] = cluster_solid_[C.child[0]];
  }
}

// A binary tree over the blockers, split at the median centre along the longest axis of the centres.
void SolidShafts::build(int node, int first, int count) {
  Bounds3 box, centres;
  for (int k = first; k < first + count; ++k) {
    const Blocker& b = blockers_[k];
    const Vector3 r{b.radius, b.radius, b.radius};
    box.add(b.centre - r);
    box.add(b.centre + r);
    centres.add(b.centre);
  }
  nodes_[node].box = box;
  if (count <= kLeafBlockers) {
    nodes_[node].first = first;
    nodes_[node].count = count;
    return;
  }
  const Vector3 extent = centres.diagonal();
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const int half = count / 2;
  std::nth_element(blockers_.begin() + first, blockers_.begin() + first + half, blockers_.begin() + first + count,
                   [axis](const Blocker& a, const Blocker& b) { return a.centre[axis] < b.centre[axis]; });
  const int left = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  build(left, first, half);
  nodes_[node].right = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  build(nodes_[node].right, first + half, count - half);
}

SolidShafts::End SolidShafts::element_end(int e) const {
  const Element& E = forest_.elements[e];
  End end;
  end.centre = E.centre;
  end.radius = E.radius;
  end.solid = element_solid_[e];
  std::copy(E.tri.v.begin(), E.tri.v.end(), end.corners.begin());
  end.count = 3;
  return end;
}

SolidShafts::End SolidShafts::cluster_end(int c) const {
  const Cluster& C = tree_.clusters[c];
  End end;
  end.centre = C.centre;
  end.radius = C.radius;
  end.solid = cluster_solid_[c];
  for (int k = 0; k < 8; ++k) end.corners[k] = C.box.corner(k);
  end.count = 8;
  return end;
}

bool SolidShafts::one_side(const Plane& plane, const End& a, const End& b, bool front_only) const {
  bool front = true, back = !front_only;
  for (const End* end : {&a, &b})
    for (int k = 0; k < end->count && (front || back); ++k) {
      const double d = dot(plane.normal, end->corners[k] - plane.on);
      front = front && d >= -tolerance_;
      back = back && d <= tolerance_;
    }
  return front || back;
}

bool SolidShafts::may_hide(const Blocker& blocker, const End& a, const End& b) const {
  if (blocker.solid < 0) return !one_side(blocker.plane, a, b, false);
  // A convex solid lies behind each of its faces' planes: one with the whole pair in front of it
  // parts them.
  for (int f = blocker.first_face; f < blocker.first_face + blocker.face_count; ++f)
    if (one_side(face_planes_[f], a, b, true)) return false;
  return true;
}

bool SolidShafts::clear(const End& a, const End& b) const {
  if (nodes_.empty()) return true;
  const double grow = std::max(a.radius, b.radius) + tolerance_;
  const Vector3 d = b.centre - a.centre;
  const std::array<double, 3> inverse = {1 / d.x, 1 / d.y, 1 / d.z};
  const BallHull hull(a.centre, a.radius, b.centre, b.radius);
  std::array<int, 64> stack;
  int top = 0, near = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!segment_meets_box(a.centre, inverse, node.box, grow)) continue;
    if (node.right >= 0) {
      stack[top++] = node.right;
      stack[top++] = static_cast<int>(&node - nodes_.data()) + 1;
      continue;
    }
    for (int k = node.first; k < node.first + node.count; ++k) {
      const Blocker& blocker = blockers_[k];
      if (blocker.convex && (blocker.solid == a.solid || blocker.solid == b.solid)) continue;  // its own
      if (hull.outside(blocker.centre) > blocker.radius + tolerance_) continue;
      if (++near > kNearBlockers || may_hide(blocker, a, b)) return false;
    }
  }
  return true;
}

}  // namespace lambert::hierarchical
