// View factors between surfaces, from the patch factors of a transport operator (the dense or the
// hierarchical method alike: only TransportOperator::apply is used, once per batch of surfaces, so
// the hierarchical method's links are summed to surfaces without forming N² factors):
//
//   F_IJ = Σ_{i∈I} A_i Σ_{j∈J} F_ij / A_I,   A_I = Σ_{i∈I} A_i            (area-weighted)
//
// Σ_{j∈J} F_ij is row i of F applied to J's indicator vector. Reciprocity A_I F_IJ = A_J F_JI holds
// as exactly as the patch factors' A_i F_ij = A_j F_ji; a closed patch row gives closed surface rows.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "solver/pipeline/hemisphere.h"
#include "solver/pipeline/transport_operator.h"
#include "solver/scene.h"

namespace lambert {

// The surfaces that are reported, as groups of the scene's surfaces: a scene's own surfaces each, or a
// View3D file's radiating surfaces with those its combination numbers merge (its obstructions are
// occluders only: in no group).
struct SurfaceGroups {
  std::vector<int> of_surface;     // per scene surface: its group, or −1 (an occluder only)
  std::vector<std::string> names;  // per group
  std::size_t size() const { return names.size(); }
  static SurfaceGroups each_surface(const Scene& scene);
};

struct ViewFactorMatrix {
  std::vector<std::string> names;  // per surface (group)
  std::vector<double> area_m2;     // A_I: its patches' areas, without patches inside closed solids
                                   // (0, with zero factors and a warning, where none is left)
  std::vector<double> F;           // S × S row-major
  std::vector<double> row_sums;    // Σ_J F_IJ over the reported surfaces
  // Per surface: the share of its view that occluders take (View3D's obstructions and null surfaces),
  // so that row_sums + to_occluders is 1 on a closed enclosure. Empty where there are none.
  std::vector<double> to_occluders;
  // max over pairs |A_I F_IJ − A_J F_JI| / min(A_I, A_J): the largest error reciprocity leaves in a
  // factor of the smaller surface of a pair (dense method: round-off).
  double reciprocity_residual = 0;
  std::vector<std::string> warnings;
  std::size_t size() const { return names.size(); }
  double at(std::size_t I, std::size_t J) const { return F[I * size() + J]; }
};

// Per patch of `op`: its group, or −1 for an occluder's patch or one inside a closed solid (it takes
// no part in the exchange).
std::vector<int> patch_groups(const TransportOperator& op, const SurfaceGroups& groups);

// The surface matrix over `groups`.
ViewFactorMatrix surface_view_factors(const TransportOperator& op, const SurfaceGroups& groups);

// The row sums and reciprocity residual of a matrix whose F and areas are set.
void measure_view_factors(ViewFactorMatrix& m);

// A content hash of the geometry that the factors depend on: the surfaces in order (names, metres,
// triangles) and which of them are reported, as "fnv1a64:" and 16 hex digits (FNV-1a over the values'
// bits). It tells a caller whether saved factors belong to a scene; it is not a cryptographic hash.
std::string geometry_hash(const Scene& scene, const SurfaceGroups& groups);

}  // namespace lambert
