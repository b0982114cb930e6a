#include "solver/pipeline/panes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

#include "mesh/convex2d.h"
#include "solver/glazing.h"

namespace lambert {
namespace {

bool transmits(const Scene& scene, const Surface& s) {
  return scene.materials[s.material].transmission != Transmission::kNone;
}

// A patch in the plane of its pane's input triangle: counter-clockwise about the front face's
// normal (a back face's patches run the other way), with its bounding box.
struct PaneLoop {
  int patch = 0;
  Loop2d loop;
  double area = 0;
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
};

PaneLoop pane_loop(const Patch& patch, int index, const Point3& origin, const Vector3& u, const Vector3& w) {
  PaneLoop out;
  out.patch = index;
  for (const Point3& v : patch.triangle.v) {
    const Vector3 d = v - origin;
    const Point2d q{dot(d, u), dot(d, w)};
    out.loop.push_back(q);
    for (int a = 0; a < 2; ++a) out.lo[a] = std::min(out.lo[a], q[a]), out.hi[a] = std::max(out.hi[a], q[a]);
  }
  out.area = signed_area(out.loop);
  if (out.area < 0) std::reverse(out.loop.begin(), out.loop.end()), out.area = -out.area;
  return out;
}

bool boxes_meet(const PaneLoop& a, const PaneLoop& b) {
  return a.lo[0] < b.hi[0] && b.lo[0] < a.hi[0] && a.lo[1] < b.hi[1] && b.lo[1] < a.hi[1];
}

}  // namespace

bool has_panes(const Scene& scene) {
  return std::any_of(scene.surfaces.begin(), scene.surfaces.end(), [&](const Surface& s) { return transmits(scene, s); });
}

bool add_pane_back_faces(Scene& scene) {
  bool any = false;
  for (Surface& s : scene.surfaces) {
    if (!transmits(scene, s) || s.pane_triangles > 0) continue;
    TriangleMesh& mesh = s.mesh;
    const std::size_t T = mesh.triangles.size();
    const int V = static_cast<int>(mesh.vertices.size());
    mesh.vertices.reserve(2 * static_cast<std::size_t>(V));
    for (int v = 0; v < V; ++v) mesh.vertices.push_back(mesh.vertices[v]);
    for (std::size_t t = 0; t < T; ++t) {
      const auto [a, b, c] = mesh.triangles[t];
      mesh.triangles.push_back({a + V, c + V, b + V});
    }
    s.two_sided.assign(2 * T, 1);
    s.pane_triangles = T;
    any = true;
  }
  return any;
}

std::vector<double> patch_transmittance(const Scene& scene, const std::vector<Patch>& patches) {
  if (!has_panes(scene)) return {};
  const std::size_t W = scene.grid.size();
  std::vector<double> tau(patches.size() * W, 0.0);
  for (std::size_t i = 0; i < patches.size(); ++i) {
    const Material& m = scene.materials[scene.surfaces[patches[i].surface].material];
    if (m.transmission == Transmission::kNone) continue;
    // Clear glass passes the interreflected light, diffuse, with the hemispherical mean of g.
    const double g = m.transmission == Transmission::kSpecular ? pane_hemispherical_factor() : 1.0;
    for (std::size_t w = 0; w < W; ++w) tau[i * W + w] = g * m.transmittance[w];
  }
  return tau;
}

PaneTransfer pane_transfer(const Scene& scene, const std::vector<Patch>& patches) {
  PaneTransfer out;
  if (!has_panes(scene)) return out;
  std::vector<int> first_input(scene.surfaces.size() + 1, 0);
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s)
    first_input[s + 1] = first_input[s] + static_cast<int>(scene.surfaces[s].mesh.triangles.size());
  // The patches of each front triangle's two faces, by the front triangle's global index.
  std::map<int, std::array<std::vector<int>, 2>> faces;
  for (std::size_t i = 0; i < patches.size(); ++i) {
    const int s = patches[i].surface;
    const auto T = static_cast<int>(scene.surfaces[s].pane_triangles);
    if (T == 0) continue;
    const int t = patches[i].input_triangle - first_input[s];
    faces[first_input[s] + t % T][t >= T].push_back(static_cast<int>(i));
  }
  std::vector<std::vector<std::pair<int, double>>> entries(patches.size());
  Loop2d piece, scratch;
  for (const auto& [front, sides] : faces) {
    const auto surface = static_cast<std::size_t>(
        std::upper_bound(first_input.begin(), first_input.end(), front) - first_input.begin() - 1);
    const Triangle tri = scene.surfaces[surface].mesh.triangle(static_cast<std::size_t>(front - first_input[surface]));
    const Vector3 n = tri.normal(), u = normalize(tri.v[1] - tri.v[0]), w = cross(n, u);
    std::array<std::vector<PaneLoop>, 2> loops;
    for (int f = 0; f < 2; ++f)
      for (int i : sides[f]) loops[f].push_back(pane_loop(patches[i], i, tri.v[0], u, w));
    for (const PaneLoop& a : loops[0])
      for (const PaneLoop& b : loops[1]) {
        if (!boxes_meet(a, b)) continue;
        clip_convex_into(a.loop, b.loop, piece, scratch);
        const double overlap = piece.size() >= 3 ? std::abs(signed_area(piece)) : 0.0;
        if (!(overlap > 0)) continue;
        entries[a.patch].push_back({b.patch, overlap / a.area});
        entries[b.patch].push_back({a.patch, overlap / b.area});
      }
  }
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (entries[i].empty()) continue;
    out.row.push_back(static_cast<int>(i));
    const Transmission kind = scene.materials[scene.surfaces[patches[i].surface].material].transmission;
    out.rays_carry_direct.push_back(kind == Transmission::kSpecular);
    for (const auto& [j, p] : entries[i]) out.col.push_back(j), out.weight.push_back(p);
    out.start.push_back(out.col.size());
  }
  return out;
}

}  // namespace lambert
