// The sources-and-direct-light stage of the solve, shared by both methods: the LightModel list
// (solver/light_model.h: the scene's lights, then every piece of a Phong-lobed emitter), each
// patch's reflectance and Lambertian emission, and the direct irradiance every source gives it.
//
// A lobed emitter reaches the other patches and the probes as direct irradiance (so M and B hold
// Lambertian emission only, and a lobed emitter's B is its reflected part ρH). With
// output.per_source, each light and each emitting surface keeps its own M and E apart (SourceTerms):
// the radiosity equation is linear in them, and the joint solve uses their sums.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "solver/light_model.h"
#include "solver/linear_solve.h"
#include "solver/radiosity.h"
#include "solver/visibility.h"
#include "solver/visible_fraction.h"

namespace lambert {

// A piece of a Phong-lobed emitting surface that becomes one direct source: a patch (dense) or a
// root element (hierarchical, whose count stays that of the roots).
struct LobedPiece {
  Triangle triangle;
  int surface = 0;
};

// One source of output.per_source: a light, or an emitting surface (all its pieces together).
struct SourceTerms {
  std::string pointer, name;
  std::vector<double> M;  // [patch][λ] its Lambertian emission (empty for a light)
  std::vector<double> E;  // [patch][λ] its direct irradiance
};

class ClearPanes;

struct DirectLight {
  std::vector<std::unique_ptr<LightModel>> sources;  // scene lights, then the lobed pieces in order
  // [patch][λ] flat: reflectance, Lambertian emission, direct irradiance from every source, and the
  // part of it from sources of known flux (flux_factor > 0: point-like lights and lobed emitters).
  std::vector<double> rho, M, E_direct, E_known_flux;
  // Glazing (panes.h): per patch and wavelength the transmittance τ (empty where no material
  // transmits), and P, what each pane face gathers of the other face's irradiance.
  std::vector<double> tau;
  PaneTransfer panes;
  // Clear glass (clear_panes.h): the channels, or null where no pane is clear; per patch and
  // wavelength the direct irradiance a clear pane's face transmits, from sources of unknown and of
  // known flux, and per patch whether it is such a face (all three empty without clear panes).
  std::shared_ptr<const ClearPanes> clear;
  std::vector<double> transmitted_unknown_flux, transmitted_known_flux;
  std::vector<char> clear_face;
  bool any_emitter = false;    // some patch emits (Lambertian)
  bool any_reflector = false;  // some patch reflects or transmits at some wavelength (ρ ≠ 0: signed in rgb mode)
  std::vector<SourceTerms> terms;   // with output.per_source: the lights, then the emitting surfaces
  std::vector<int> term_of_source;  // per source: its term, or −1

  // Whether radiosity can flow between patches: something emits, or a source lights a reflector.
  bool needs_transport() const { return any_emitter || (any_reflector && !sources.empty()); }

  // Patches inside closed solids neither emit nor reflect: their ρ, τ and M (and their terms' M) are 0.
  void leave_out_enclosed(const std::vector<Hemisphere>& hemisphere, std::size_t W);
};

// The stage: `lobed` lists the pieces of Phong-lobed emitters in order; `vis` shadows the sources'
// patch factors. Throws SolveCancelled when control.cancel is set.
DirectLight direct_light(const Scene& scene, const std::vector<Patch>& patches, std::span<const LobedPiece> lobed,
                         const Visibility& vis, const SolveControl& control);

// The pieces of lobed emitters among the patches, in patch order.
std::vector<LobedPiece> lobed_patches(const Scene& scene, const std::vector<Patch>& patches);

}  // namespace lambert
