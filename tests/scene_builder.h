// Builds Scenes in code for solver tests (independent of the JSON codec).
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "solver/radiosity.h"
#include "solver/scene.h"
#include "tests/test_geometry.h"

namespace lambert::test {

class SceneBuilder {
 public:
  explicit SceneBuilder(std::vector<double> wavelengths_nm = {555}) {
    scene_.grid = WavelengthGrid::from_list(std::move(wavelengths_nm));
  }
  std::size_t W() const { return scene_.grid.size(); }

  int material(const std::string& name, double rho) {
    scene_.materials.push_back({name, std::vector<double>(W(), rho), std::nullopt, Transmission::kNone, {}});
    return static_cast<int>(scene_.materials.size()) - 1;
  }
  // A surface from triangles (front side counter-clockwise); emission is a constant exitance.
  Surface& surface(const std::string& name, int material, const std::vector<Triangle>& triangles,
                   double exitance = 0) {
    Surface s;
    s.name = name;
    s.material = material;
    s.pointer = "/surfaces/" + std::to_string(scene_.surfaces.size());
    for (const Triangle& t : triangles) {
      const int base = static_cast<int>(s.mesh.vertices.size());
      for (const Point3& p : t.v) s.mesh.vertices.push_back(p);
      s.mesh.triangles.push_back({base, base + 1, base + 2});
    }
    if (exitance > 0) s.emission = Emission{std::vector<double>(W(), exitance), 1.0};
    scene_.surfaces.push_back(std::move(s));
    return scene_.surfaces.back();
  }
  void point_light(const Point3& position, double intensity) {
    PointLight l;
    l.position = position;
    l.intensity_W_sr_nm.assign(W(), intensity);
    scene_.lights.push_back(l);
    scene_.light_pointers.push_back("/lights/" + std::to_string(scene_.lights.size() - 1));
  }
  void probe(const std::string& name, const Point3& p, const Vector3& n) {
    Probe probe;
    probe.name = name;
    probe.points = {p};
    probe.normal = n;
    scene_.probes.push_back(std::move(probe));
  }
  void max_patch_area(double a) { scene_.meshing.max_patch_area_m2 = a; }
  Scene& scene() { return scene_; }

 private:
  Scene scene_;
};

// Area-weighted mean of a per-patch quantity ([patch][λ] flat) over one surface, at wavelength w.
inline double surface_mean(const Solution& sol, int surface, const std::vector<double>& values, std::size_t w = 0) {
  double sum = 0, area = 0;
  for (std::size_t i = 0; i < sol.patches.size(); ++i) {
    if (sol.patches[i].surface != surface) continue;
    sum += sol.patches[i].area_m2 * values[i * sol.wavelengths() + w];
    area += sol.patches[i].area_m2;
  }
  return sum / area;
}

// Axis-aligned box [lo, hi] as 6 rectangles (12 triangles), normals pointing inward (a room) or
// outward (an obstacle).
inline std::vector<Triangle> box(const Point3& lo, const Point3& hi, bool inward) {
  std::vector<Triangle> out;
  for_each_box_face(lo, hi, [&](const Point3& o, const Vector3& u, const Vector3& v) {
    for (const Triangle& t : inward ? rectangle(o, u, v) : rectangle(o, v, u)) out.push_back(t);
  });
  return out;
}

// A sphere of radius r about c as an icosahedron whose faces are split 1:4 `level` times, the new
// vertices pushed out to the sphere (20 × 4^level triangles), normals pointing outward: a faceted
// object whose triangles lie in as many planes as there are triangles.
inline std::vector<Triangle> icosphere(const Point3& c, double r, int level) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vector3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (Vector3& p : v) p = normalize(p);
  std::vector<std::array<Vector3, 3>> faces;
  for (const auto& [a, b, d] : std::vector<std::array<int, 3>>{
           {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
           {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}})
    faces.push_back({v[a], v[b], v[d]});
  for (int l = 0; l < level; ++l) {
    std::vector<std::array<Vector3, 3>> finer;
    for (const auto& [a, b, d] : faces) {
      const Vector3 ab = normalize(a + b), bd = normalize(b + d), da = normalize(d + a);
      finer.insert(finer.end(), {{a, ab, da}, {b, bd, ab}, {d, da, bd}, {ab, bd, da}});
    }
    faces.swap(finer);
  }
  std::vector<Triangle> out;
  for (const auto& [a, b, d] : faces) out.push_back(Triangle{{c + r * a, c + r * b, c + r * d}});
  return out;
}

}  // namespace lambert::test
