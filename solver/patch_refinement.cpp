// Splitting patches where the light varies (patch_refinement.h).
#include "solver/patch_refinement.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "solver/cubature.h"
#include "solver/form_factor.h"
#include "solver/light_model.h"
#include "solver/pipeline/clear_panes.h"
#include "solver/visible_fraction.h"

namespace lambert {

std::vector<Point3> lifted_visibility_samples(const std::vector<Patch>& patches, const Visibility& vis) {
  std::vector<Point3> out(patches.size() * kMaxVisibilitySamples);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, patches.size(), 256), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      for (int k = 0; k < kMaxVisibilitySamples; ++k)
        out[i * kMaxVisibilitySamples + k] = vis.lift(visibility_sample(patches[i].triangle, k), patches[i].normal);
  });
  return out;
}

std::size_t patch_visible_fractions(std::size_t a, std::span<const std::size_t> partners,
                                    const std::vector<Patch>& patches, std::span<const Point3> samples,
                                    const Visibility& vis, std::span<double> fractions) {
  const Point3* near = &samples[a * kMaxVisibilitySamples];
  const Vector3 na = patches[a].normal;
  return weighted_visible_fractions(
      vis, partners.size(),
      [&](std::size_t l, int k) {
        return std::pair{near[k], samples[partners[l] * kMaxVisibilitySamples + paired_sample(k)]};
      },
      [&](std::size_t l, const Point3& p, const Point3& q) { return link_weight(p, na, q, patches[partners[l]].normal); },
      fractions);
}

constexpr double kCoplanarCos = 0.9999;  // normals within about 0.8°

// Marks the patches whose quantity q (an irradiance, radiometric total Σ_λ w_λ H(λ)) is more than
// `ratio` times a neighbour's (same surface and plane, sharing a vertex), or less than 1/ratio of it,
// and differs from it by more than 0.1 % of the area-weighted mean of q: shadow boundaries, contacts
// and hot spots, not smooth or dark regions.
std::vector<char> where_varies(const std::vector<Patch>& patches, const std::vector<double>& q, double ratio) {
  const std::size_t N = patches.size();
  double mean = 0, area = 0;
  for (std::size_t i = 0; i < N; ++i) {
    mean += q[i] * patches[i].area_m2;
    area += patches[i].area_m2;
  }
  mean = area > 0 ? mean / area : 0;
  // Neighbours: patches of one surface that share a vertex (exact positions: subdivision splits
  // shared edges at their exact midpoints).
  std::map<std::tuple<int, double, double, double>, std::vector<std::size_t>> at_vertex;
  for (std::size_t i = 0; i < N; ++i)
    for (const Point3& v : patches[i].triangle.v) at_vertex[{patches[i].surface, v.x, v.y, v.z}].push_back(i);
  std::vector<char> marked(N, 0);
  for (const auto& [key, list] : at_vertex)
    for (std::size_t a = 0; a < list.size(); ++a)
      for (std::size_t b = a + 1; b < list.size(); ++b) {
        const std::size_t i = list[a], j = list[b];
        // Across a crease (a wall meeting a ceiling of the same surface) the light may jump without
        // any shadow: only neighbours in one plane are compared.
        if (dot(patches[i].normal, patches[j].normal) < kCoplanarCos) continue;
        const double hi = std::max(q[i], q[j]), lo = std::min(q[i], q[j]);
        if (hi > ratio * lo && hi - lo > 1e-3 * mean) marked[i] = marked[j] = 1;
      }
  return marked;
}

// The marked patches split 1:4 (those that would fall below min_area are not). Returns the patches
// unchanged (same size) when nothing is split.
std::vector<Patch> split_marked(const std::vector<Patch>& patches, const std::vector<char>& marked, double min_area) {
  std::vector<Patch> out;
  out.reserve(patches.size());
  for (std::size_t i = 0; i < patches.size(); ++i) {
    if (!marked[i] || patches[i].area_m2 / 4 < min_area) {
      out.push_back(patches[i]);
      continue;
    }
    for (const Triangle& t : split4(patches[i].triangle)) {
      Patch p = patches[i];
      p.triangle = t;
      p.area_m2 = t.area();
      out.push_back(p);
    }
  }
  return out;
}

// Marks the patches that a probe point sees from closer than 0.55 times the patch's longest edge
// (the distance to the centroid): the point's irradiance then depends on how the radiosity varies
// across the patch, which a constant patch does not resolve (a probe beside a box's shaded side).
// The probe points are hashed into cubes as large as the largest such distance.
void mark_near_probes(const std::vector<Patch>& patches, const std::vector<Probe>& probes, std::vector<char>& marked) {
  std::vector<std::pair<Point3, Vector3>> points;
  for (const Probe& probe : probes)
    for (const Point3& p : probe.points) points.push_back({p, probe.normal});
  if (points.empty() || patches.empty()) return;
  std::vector<double> reach2(patches.size());  // squared distance within which a point counts as near
  double cell = 0;
  for (std::size_t i = 0; i < patches.size(); ++i) {
    const Triangle& t = patches[i].triangle;
    double edge2 = 0;
    for (int k = 0; k < 3; ++k) edge2 = std::max(edge2, length_squared(t.v[(k + 1) % 3] - t.v[k]));
    reach2[i] = 0.3 * edge2;
    cell = std::max(cell, std::sqrt(reach2[i]));
  }
  if (!(cell > 0)) return;
  using Key = std::tuple<long long, long long, long long>;
  auto key = [&](const Point3& p) {
    return Key{static_cast<long long>(std::floor(p.x / cell)), static_cast<long long>(std::floor(p.y / cell)),
               static_cast<long long>(std::floor(p.z / cell))};
  };
  std::map<Key, std::vector<std::size_t>> cells;
  for (std::size_t k = 0; k < points.size(); ++k) cells[key(points[k].first)].push_back(k);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, patches.size(), 64), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const Patch& a = patches[i];
      const Point3 c = a.triangle.centroid();
      const auto [cx, cy, cz] = key(c);
      for (long long dx = -1; dx <= 1 && !marked[i]; ++dx)
        for (long long dy = -1; dy <= 1 && !marked[i]; ++dy)
          for (long long dz = -1; dz <= 1 && !marked[i]; ++dz) {
            const auto it = cells.find({cx + dx, cy + dy, cz + dz});
            if (it == cells.end()) continue;
            for (std::size_t k : it->second) {
              // Named references, not a structured binding: clang before 16 cannot capture a binding in
              // the lambda below (P1091), and the fuzz build (docs/FUZZING.md) uses Debian's clang 14.
              const Point3& p = points[k].first;
              const Vector3& n = points[k].second;
              if (length_squared(p - c) < reach2[i] && dot(p - c, a.normal) > 0 &&
                  std::any_of(a.triangle.v.begin(), a.triangle.v.end(), [&](const Point3& v) { return dot(v - p, n) > 0; })) {
                marked[i] = 1;
                break;
              }
            }
          }
    }
  });
}

// The direct irradiance of each patch, radiometric total Σ_λ w_λ E(λ): from the scene's lights and
// from emitting surfaces (LightModel::patch_factor). An emitting surface sends the same radiance from
// every point of an input triangle, so each emitting input triangle is one source, however finely it
// is meshed: the exact point value (Lambert's contour integral, or the Phong lobe's moments) over the
// receiver, times the kernel-weighted visible fraction of the triangle. Each emitting patch as a
// source would cost N × (emitting patches) exact factors, more than the rest of the meshing.
// Emitting surfaces are left out where they are more than an eighth of the patches (a furnace: every
// patch emits), whose direct light varies with nothing the refinement should resolve. Light through
// clear glass counts (solver/pipeline/clear_panes.h): the sun's patch through a window has edges too.
std::vector<double> direct_irradiance_totals(const Scene& scene, const std::vector<Patch>& patches,
                                             const Visibility& vis, const SolveControl& control) {
  const std::size_t N = patches.size(), W = scene.grid.size();
  std::vector<std::unique_ptr<LightModel>> sources = make_scene_light_models(scene);
  const std::size_t emitting = static_cast<std::size_t>(std::count_if(
      patches.begin(), patches.end(), [&](const Patch& p) { return scene.surfaces[p.surface].emission.has_value(); }));
  if (emitting > 0 && emitting <= N / 8) {
    const std::vector<Triangle> inputs = input_triangles(scene);
    std::vector<char> taken(inputs.size(), 0);
    for (const Patch& p : patches) {
      const std::optional<Emission>& e = scene.surfaces[p.surface].emission;
      if (!e || taken[p.input_triangle]) continue;
      taken[p.input_triangle] = 1;
      sources.push_back(make_phong_emitter(inputs[p.input_triangle], e->lobe_exponent, e->exitance_W_m2_nm));
    }
  }
  std::vector<double> source_total(sources.size(), 0.0);
  for (std::size_t k = 0; k < sources.size(); ++k) {
    const std::vector<double>& spectrum = sources[k]->spectrum();
    for (std::size_t w = 0; w < W; ++w) source_total[k] += scene.grid.weight_nm[w] * spectrum[w];
  }
  std::vector<double> q(N, 0.0);
  const ClearPanes clear(scene);  // the light through clear glass (none without it)
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 8), [&](const auto& range) {
    std::vector<double> through;
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      if (control.cancel && control.cancel->load(std::memory_order_relaxed)) return;
      for (std::size_t k = 0; k < sources.size(); ++k)
        if (source_total[k] != 0) q[i] += source_total[k] * sources[k]->patch_factor(patches[i].triangle, vis);
      if (clear.empty()) continue;
      for (const auto& source : sources) {
        auto factor = [&](const Visibility& v) { return source->patch_factor(patches[i].triangle, v); };
        if (clear.through(*source, factor, through))
          for (std::size_t w = 0; w < W; ++w) q[i] += scene.grid.weight_nm[w] * through[w];
      }
    }
  });
  if (control.cancel && control.cancel->load(std::memory_order_relaxed)) throw SolveCancelled();
  return q;
}

bool has_direct_light(const Scene& scene) {
  return !scene.lights.empty() ||
         std::any_of(scene.surfaces.begin(), scene.surfaces.end(), [](const Surface& s) { return s.emission.has_value(); });
}

}  // namespace lambert
