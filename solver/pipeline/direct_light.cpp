#include "solver/pipeline/direct_light.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "solver/pipeline/clear_panes.h"
#include "solver/pipeline/panes.h"

namespace lambert {
namespace {

// output.per_source: a term per light, then per emitting surface; each source's term.
void make_terms(const Scene& scene, const std::vector<Patch>& patches, std::span<const LobedPiece> lobed,
                DirectLight& d) {
  const std::size_t N = patches.size(), W = scene.grid.size();
  d.term_of_source.assign(d.sources.size(), -1);
  if (!scene.output.per_source) return;
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    d.terms.push_back({l < scene.light_pointers.size() ? scene.light_pointers[l] : "/lights/" + std::to_string(l),
                       std::string(d.sources[l]->kind()), {}, std::vector<double>(N * W, 0.0)});
    d.term_of_source[l] = static_cast<int>(l);
  }
  std::vector<int> term_of_surface(scene.surfaces.size(), -1);
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s)
    if (scene.surfaces[s].emission) {
      term_of_surface[s] = static_cast<int>(d.terms.size());
      d.terms.push_back({scene.surfaces[s].pointer, scene.surfaces[s].name, std::vector<double>(N * W, 0.0),
                         std::vector<double>(N * W, 0.0)});
    }
  for (std::size_t p = 0; p < lobed.size(); ++p) d.term_of_source[scene.lights.size() + p] = term_of_surface[lobed[p].surface];
  for (std::size_t i = 0; i < N; ++i) {
    const Surface& surface = scene.surfaces[patches[i].surface];
    if (!surface.emission || surface.emission->lobe_exponent != 1.0) continue;
    SourceTerms& t = d.terms[term_of_surface[patches[i].surface]];
    for (std::size_t w = 0; w < W; ++w) t.M[i * W + w] = d.M[i * W + w];
  }
}

}  // namespace

std::vector<LobedPiece> lobed_patches(const Scene& scene, const std::vector<Patch>& patches) {
  std::vector<LobedPiece> out;
  for (const Patch& p : patches) {
    const Surface& s = scene.surfaces[p.surface];
    if (s.emission && s.emission->lobe_exponent != 1.0) out.push_back({p.triangle, p.surface});
  }
  return out;
}

DirectLight direct_light(const Scene& scene, const std::vector<Patch>& patches, std::span<const LobedPiece> lobed,
                         const Visibility& vis, const SolveControl& control) {
  const std::size_t N = patches.size(), W = scene.grid.size();
  DirectLight d;
  d.rho.resize(N * W);
  d.M.assign(N * W, 0.0);
  d.E_direct.assign(N * W, 0.0);
  d.E_known_flux.assign(N * W, 0.0);
  d.sources = make_scene_light_models(scene);
  for (const LobedPiece& piece : lobed) {
    const Emission& e = *scene.surfaces[piece.surface].emission;
    d.sources.push_back(make_phong_emitter(piece.triangle, e.lobe_exponent, e.exitance_W_m2_nm));
  }
  for (std::size_t i = 0; i < N; ++i) {
    const Surface& s = scene.surfaces[patches[i].surface];
    const auto& refl = scene.materials[s.material].reflectance;
    for (std::size_t w = 0; w < W; ++w) {
      d.rho[i * W + w] = refl[w];
      d.any_reflector |= refl[w] != 0;
    }
    if (s.emission && s.emission->lobe_exponent == 1.0) {
      for (std::size_t w = 0; w < W; ++w) d.M[i * W + w] = s.emission->exitance_W_m2_nm[w];
      d.any_emitter = true;
    }
  }
  d.tau = patch_transmittance(scene, patches);
  d.any_reflector |= std::any_of(d.tau.begin(), d.tau.end(), [](double t) { return t != 0; });
  d.panes = pane_transfer(scene, patches);
  make_terms(scene, patches, lobed, d);
  if (!d.sources.empty()) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 16), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        for (std::size_t k = 0; k < d.sources.size(); ++k) {
          const auto& source = d.sources[k];
          const double g = source->patch_factor(patches[i].triangle, vis);
          if (g == 0) continue;
          const auto& S = source->spectrum();
          const bool known_flux = source->flux_factor() > 0;
          double* own = d.term_of_source[k] >= 0 ? &d.terms[d.term_of_source[k]].E[i * W] : nullptr;
          for (std::size_t w = 0; w < W; ++w) {
            d.E_direct[i * W + w] += g * S[w];
            if (known_flux) d.E_known_flux[i * W + w] += g * S[w];
            if (own) own[w] += g * S[w];
          }
        }
      }
    });
  }
  add_direct_through_panes(d, scene, patches);
  if (control.cancel && control.cancel->load(std::memory_order_relaxed)) throw SolveCancelled();
  return d;
}

void DirectLight::leave_out_enclosed(const std::vector<Hemisphere>& hemisphere, std::size_t W) {
  for (std::size_t i = 0; i < hemisphere.size(); ++i)
    if (hemisphere[i] == Hemisphere::Enclosed)
      for (std::size_t w = 0; w < W; ++w) {
        rho[i * W + w] = 0, M[i * W + w] = 0;
        if (!tau.empty()) tau[i * W + w] = 0;
        for (SourceTerms& term : terms)
          if (!term.M.empty()) term.M[i * W + w] = 0;
      }
}

}  // namespace lambert
