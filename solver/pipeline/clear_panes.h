// Clear glass in the direct light (SPEC §5 "Glazing", docs/METHOD.md "Clear glass"): a source's ray
// that crosses one pane of "transmission": "specular" arrives with τ(λ) g(θ) (solver/glazing.h).
// Visibility is a scalar and τ a spectrum, so the clear materials are channels: a source's factor
// is taken through the solve's own Visibility, where panes block, and once more per channel c
// through a view that counts only the rays crossing one pane of c, g(θ) each
// (Visibility::through_panes), and
//   E(λ) = S(λ) [g_open + Σ_c τ_c(λ) g_c].
// A scene without clear panes has no channel: its direct light is the first term alone, as before.
//
// What a clear pane's face transmits of the direct light, T(λ) = τ(λ) × its incident irradiance
// weighted by g of each ray's incidence, is the same factor taken from just behind the face through
// its own channel; the energy certificate counts it (transmitted + reflected + absorbed = received).
// A ray that would cross two panes is refused (Visibility::transmitted): one factor τ_c(λ) per
// channel cannot say how many panes a ray crossed.
#pragma once

#include <memory>
#include <vector>

#include "solver/light_model.h"
#include "solver/radiosity.h"
#include "solver/visibility.h"

namespace lambert {

class ClearPanes {
 public:
  // The scene as solved (with its panes' back faces, panes.h). Empty where no material is clear.
  explicit ClearPanes(const Scene& scene);
  bool empty() const { return views_.empty(); }

  // The channel of a surface's material, or −1 where it is not clear glass.
  int channel_of_surface(int surface) const { return channel_of_surface_[surface]; }
  const Visibility& view(int channel) const { return *views_[channel]; }

  // out[w] = S(λ_w) Σ_c τ_c(λ_w) factor(view c), factor(vis) a source's geometric factor through a
  // Visibility. Returns false (out untouched) where nothing crosses a pane, and for a source whose
  // light takes no rays (ambient).
  template <class Factor>
  bool through(const LightModel& source, Factor&& factor, std::vector<double>& out) const {
    if (empty() || source.directionless()) return false;
    bool any = false;
    for (std::size_t c = 0; c < views_.size(); ++c) {
      const double g = factor(*views_[c]);
      if (g == 0) continue;
      if (!any) out.assign(W_, 0.0), any = true;
      for (std::size_t w = 0; w < W_; ++w) out[w] += g * tau_[c][w];
    }
    if (any)
      for (std::size_t w = 0; w < W_; ++w) out[w] *= source.spectrum()[w];
    return any;
  }

  // Triangle t of a clear pane's face moved just behind it (2 lifts along −n), so that a source's
  // rays from it cross the face's own pane.
  Triangle behind(const Triangle& t) const;

 private:
  std::size_t W_ = 0;
  std::vector<Triangle> triangles_;             // the occluders, the scene's input triangles
  std::unique_ptr<Visibility> vis_;             // over them, clear panes marked
  std::vector<std::unique_ptr<Visibility>> views_;  // per channel
  std::vector<std::vector<double>> tau_;        // per channel: τ(λ) at normal incidence
  std::vector<int> channel_of_surface_;
};

struct DirectLight;

// Adds each source's light through clear panes to the patches' direct irradiance (d.E_direct,
// d.E_known_flux, the sources' terms) and fills d.transmitted_* with what clear faces pass on.
void add_direct_through_panes(DirectLight& d, const Scene& scene, const std::vector<Patch>& patches);

}  // namespace lambert
