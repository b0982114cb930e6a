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
// Phong-lobed emitting patches (LightModel::patch_factor) and from Lambertian emitting patches (the
// exact area factor times the visible fraction from rays, as in the dense solve). Emitting surfaces
// are left out where they are more than an eighth of the patches (a furnace: every patch emits),
// which would make this as costly as the solve itself.
std::vector<double> direct_irradiance_totals(const Scene& scene, const std::vector<Patch>& patches,
                                             const Visibility& vis, const SolveControl& control) {
  const std::size_t N = patches.size(), W = scene.grid.size();
  auto total = [&](const std::vector<double>& spectrum) {
    double t = 0;
    for (std::size_t w = 0; w < W; ++w) t += scene.grid.weight_nm[w] * spectrum[w];
    return t;
  };
  std::vector<std::unique_ptr<LightModel>> sources = make_scene_light_models(scene);
  std::vector<std::size_t> emitters;  // Lambertian emitting patches
  for (std::size_t i = 0; i < N; ++i)
    if (scene.surfaces[patches[i].surface].emission) emitters.push_back(i);
  if (emitters.size() > N / 8) emitters.clear();
  std::vector<double> exitance(emitters.size());
  for (std::size_t k = 0; k < emitters.size(); ++k) {
    const Patch& p = patches[emitters[k]];
    const Emission& e = *scene.surfaces[p.surface].emission;
    if (e.lobe_exponent != 1.0) sources.push_back(make_phong_emitter(p.triangle, e.lobe_exponent, e.exitance_W_m2_nm));
    else exitance[k] = total(e.exitance_W_m2_nm);
  }
  std::vector<double> source_total(sources.size());
  for (std::size_t k = 0; k < sources.size(); ++k) source_total[k] = total(sources[k]->spectrum());
  const std::vector<Point3> samples = emitters.empty() ? std::vector<Point3>{} : lifted_visibility_samples(patches, vis);
  std::vector<double> q(N, 0.0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 8), [&](const auto& range) {
    thread_local std::vector<std::size_t> partners;
    thread_local std::vector<double> unoccluded, fraction;
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      if (control.cancel && control.cancel->load(std::memory_order_relaxed)) return;
      const Patch& a = patches[i];
      for (std::size_t k = 0; k < sources.size(); ++k)
        if (source_total[k] != 0) q[i] += source_total[k] * sources[k]->patch_factor(a.triangle, vis);
      partners.clear(), unoccluded.clear();
      for (std::size_t k = 0; k < emitters.size(); ++k) {
        const Patch& b = patches[emitters[k]];
        if (exitance[k] == 0 || emitters[k] == i || !any_in_front(a.triangle, a.normal, b.triangle) ||
            !any_in_front(b.triangle, b.normal, a.triangle))
          continue;
        const double g = exchange_area(a.triangle, b.triangle);
        if (g <= 0) continue;
        partners.push_back(emitters[k]);
        unoccluded.push_back(g / a.area_m2 * exitance[k]);
      }
      if (partners.empty()) continue;
      fraction.resize(partners.size());
      patch_visible_fractions(i, partners, patches, samples, vis, fraction);
      for (std::size_t l = 0; l < partners.size(); ++l) q[i] += unoccluded[l] * fraction[l];
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
