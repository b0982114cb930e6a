#include "solver/pipeline/clear_panes.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "solver/glazing.h"
#include "solver/pipeline/direct_light.h"

namespace lambert {

ClearPanes::ClearPanes(const Scene& scene) : W_(scene.grid.size()) {
  const std::vector<int> channel_of_material = clear_glass_channels(scene);
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    if (channel_of_material[m] >= 0) tau_.push_back(scene.materials[m].transmittance);
  channel_of_surface_.assign(scene.surfaces.size(), -1);
  bool any = false;
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    channel_of_surface_[s] = channel_of_material[scene.surfaces[s].material];
    any |= channel_of_surface_[s] >= 0;
  }
  if (!any) return;
  std::vector<int> channel_of_occluder, surface_of_occluder;
  std::vector<std::string> names;
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    names.push_back(scene.surfaces[s].name);
    for (std::size_t t = 0; t < scene.surfaces[s].mesh.triangles.size(); ++t) {
      triangles_.push_back(scene.surfaces[s].mesh.triangle(t));
      channel_of_occluder.push_back(channel_of_surface_[s]);
      surface_of_occluder.push_back(static_cast<int>(s));
    }
  }
  vis_ = std::make_unique<Visibility>(triangles_);
  vis_->set_specular_panes(triangles_, std::move(channel_of_occluder),
                           [names = std::move(names), surface = std::move(surface_of_occluder)](int t) {
                             return names[surface[t]];
                           });
  for (std::size_t c = 0; c < tau_.size(); ++c) views_.push_back(vis_->through_panes(static_cast<int>(c)));
}

Triangle ClearPanes::behind(const Triangle& t) const {
  const Vector3 back = t.normal() * -2.0;  // lift() moves by its distance times this vector's length
  return Triangle{{vis_->lift(t.v[0], back), vis_->lift(t.v[1], back), vis_->lift(t.v[2], back)}};
}

void add_direct_through_panes(DirectLight& d, const Scene& scene, const std::vector<Patch>& patches) {
  auto clear = std::make_shared<const ClearPanes>(scene);
  if (clear->empty()) return;
  d.clear = clear;
  const std::size_t N = patches.size(), W = scene.grid.size();
  d.transmitted_unknown_flux.assign(N * W, 0.0);
  d.transmitted_known_flux.assign(N * W, 0.0);
  d.clear_face.assign(N, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 16), [&](const auto& range) {
    std::vector<double> E;
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const Triangle& tri = patches[i].triangle;
      const int own = clear->channel_of_surface(patches[i].surface);
      d.clear_face[i] = own >= 0;
      // A face of a clear pane passes on what it sees from just behind it, through its own pane.
      const Triangle back = own >= 0 ? clear->behind(tri) : tri;
      const std::vector<double>* tau =
          own >= 0 ? &scene.materials[scene.surfaces[patches[i].surface].material].transmittance : nullptr;
      for (std::size_t k = 0; k < d.sources.size(); ++k) {
        const LightModel& source = *d.sources[k];
        const bool known = source.flux_factor() > 0;
        if (clear->through(source, [&](const Visibility& v) { return source.patch_factor(tri, v); }, E)) {
          double* term = d.term_of_source[k] >= 0 ? &d.terms[d.term_of_source[k]].E[i * W] : nullptr;
          for (std::size_t w = 0; w < W; ++w) {
            d.E_direct[i * W + w] += E[w];
            if (known) d.E_known_flux[i * W + w] += E[w];
            if (term) term[w] += E[w];
          }
        }
        if (own < 0) continue;
        const double g = source.directionless() ? 0.0 : source.patch_factor(back, clear->view(own));
        if (g == 0) continue;
        const auto& S = source.spectrum();
        double* T = known ? &d.transmitted_known_flux[i * W] : &d.transmitted_unknown_flux[i * W];
        for (std::size_t w = 0; w < W; ++w) T[w] += g * (*tau)[w] * S[w];
      }
    }
  });
}

}  // namespace lambert
