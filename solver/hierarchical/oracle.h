// The radiosity the refinement's oracle (refiner.h) weighs each link's error bound with: per leaf the
// largest |B| over the spectral systems, pulled up to elements (area mean) and clusters (max).
#pragma once

#include <vector>

#include "solver/hierarchical/hierarchy.h"
#include "solver/pipeline/spectral_systems.h"
#include "solver/visible_fraction.h"

namespace lambert::hierarchical {

struct OracleRadiosity {
  std::vector<double> leaf_B;  // per leaf
  double power = 0;            // Σ A B over the leaves that are not enclosed
};

// From the systems' current radiosity (before the first solve, the first bounce M + ρ E). With
// `with_ambient` (the first round), unlit reflectors are given ρ times the mean interreflected
// irradiance they will receive. `shoots` per leaf: it emits or reflects at some wavelength.
OracleRadiosity oracle_radiosity(const Hierarchy& h, const SpectralSystems& systems,
                                 const std::vector<Hemisphere>& hemisphere, const std::vector<char>& shoots,
                                 bool with_ambient);

// How each cluster sends under a radiosity, which its links' factors are shaped by (Refiner).
struct ClusterSending {
  // Where its power comes from: Σ A B x / Σ A B over the leaves below (x their centroids), the box's
  // centre where it sends nothing. A cluster link's one-point estimate is taken from there: the box's
  // centre misses the radiosity's first moment over the cluster, and a sphere lit from above sends
  // most from its top, nearer a ceiling than the centre.
  std::vector<Point3> source;
  // What it sends (SentFacets), by which its links read their bins (cluster_view).
  std::vector<SentFacets> sent;
};

// How each cluster sends under `leaf_B` (≥ 0 per leaf), and the largest leaf_B below each cluster.
ClusterSending cluster_sending(const Hierarchy& h, const std::vector<double>& leaf_B, std::vector<double>& largest);

struct OracleValues {
  std::vector<double> element_B;  // area mean of the leaves below
  std::vector<double> cluster_B;  // the largest leaf below
  ClusterSending sending;
  // How far the radiosity below each element departs from a linear field over it: the largest, over
  // the element and the elements below it, of |B_centre − (B_0 + B_1 + B_2) / 3| over its children
  // (a linear field gives the centre child the mean of the three corner children, since each child's
  // mean is the field at its centroid). An element link reads its source's linear field (links.h);
  // where the radiosity dips within the source (a wall in front of an object close to it), the link
  // errs by its factor times this.
  std::vector<double> element_departure;
};
OracleValues oracle_values(const Hierarchy& h, const std::vector<double>& leaf_B);

}  // namespace lambert::hierarchical
