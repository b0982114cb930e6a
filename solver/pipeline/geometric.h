// The transport operator of a scene's geometry alone, for view factors and radiant exchange
// (solver/thermal/): the scene prepared (prepare.h), discretised by its method, and the operator
// built as if every patch sent unit radiosity (TransportOperator::build_geometric). No light, no
// spectral system: the same stages as a solve's up to its rounds.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "solver/pipeline/prepare.h"
#include "solver/pipeline/transport_operator.h"

namespace lambert {

struct GeometricOperator {
  std::unique_ptr<PreparedScene> prepared;  // the scene the operator was made for (it refers to it)
  std::unique_ptr<TransportOperator> op;
  // The operator's patches where the given scene lies (a scene far from the origin is prepared about
  // its centre), for output.
  std::vector<Patch> patches;
  SolveStats stats;                   // meshing, visibility, form factors, closure and reciprocity
  std::vector<std::string> warnings;  // the scene's and the preparation's
  const Scene& scene() const { return prepared->scene(); }  // as meshed (probes, surfaces)
};

// The method: the scene's, or for "auto" the dense one up to its patch limit (kMaxDensePatches), the
// hierarchical one beyond. Throws SolveError where a patch limit is exceeded.
GeometricOperator build_geometric_operator(const Scene& scene, const SolveControl& control);

}  // namespace lambert
