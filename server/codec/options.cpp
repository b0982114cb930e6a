// "meshing", "solver" and "output" (SPEC §1): how the scene is discretised and solved and what the
// result holds. Every key is optional; absent keys keep the defaults of solver/scene.h.
#include "server/codec/sections.h"

namespace lambert::codec {
namespace {

void decode_meshing(Decoder& d, const json& m, MeshingOptions& meshing, double unit_m) {
  if (const json* a = d.member(m, "max_patch_area"))
    if (auto v = d.number_in(*a, "/meshing/max_patch_area", 0, false, INFINITY, false))
      meshing.max_patch_area_m2 = *v * unit_m * unit_m;  // units² -> m²
  if (const json* a = d.member(m, "adaptive"))
    if (auto v = d.boolean(*a, "/meshing/adaptive")) meshing.adaptive = *v;
  if (const json* r = d.member(m, "refine_direct"))
    if (auto v = d.boolean(*r, "/meshing/refine_direct")) meshing.refine_direct = *v;
}

void decode_solver(Decoder& d, const json& s, SolverOptions& solver) {
  if (const json* t = d.member(s, "tolerance"))
    if (auto v = d.number_in(*t, "/solver/tolerance", 0, false, 0.1, true)) solver.tolerance = *v;
  if (const json* t = d.member(s, "max_iterations"))
    if (auto v = d.whole(*t, "/solver/max_iterations", 1, 1000000))
      solver.max_iterations = static_cast<int>(*v);
  if (const json* t = d.member(s, "method"))
    if (auto v = d.string(*t, "/solver/method")) {
      if (*v == "auto") solver.method = SolverMethod::Auto;
      else if (*v == "dense") solver.method = SolverMethod::Dense;
      else if (*v == "hierarchical") solver.method = SolverMethod::Hierarchical;
      else
        d.error("/solver/method", "unknown method \"" + *v +
                                      "\" (expected \"auto\", \"dense\" or \"hierarchical\")");
    }
  if (const json* t = d.member(s, "accuracy"))
    if (auto v = d.number_in(*t, "/solver/accuracy", 0, false, 0.1, true)) solver.accuracy = *v;
  if (const json* t = d.member(s, "exact_visibility"))
    if (auto v = d.boolean(*t, "/solver/exact_visibility")) solver.exact_visibility = *v;
}

void decode_output(Decoder& d, const json& o, OutputOptions& output) {
  if (const json* s = d.member(o, "spectral"))
    if (auto v = d.boolean(*s, "/output/spectral")) output.spectral = *v;
  if (const json* s = d.member(o, "per_source"))
    if (auto v = d.boolean(*s, "/output/per_source")) output.per_source = *v;
  if (const json* v = d.member(o, "view_factors"))
    if (auto b = d.boolean(*v, "/output/view_factors")) output.view_factors = *b;
  if (const json* v = d.member(o, "error_estimate"))
    if (auto b = d.boolean(*v, "/output/error_estimate")) output.error_estimate = *b;
  if (const json* v = d.member(o, "ugr_tables"))
    if (auto b = d.boolean(*v, "/output/ugr_tables")) output.ugr_tables = *b;
}

}  // namespace

void decode_options(Decoder& d, const json& doc) {
  Scene& scene = d.scene();
  const json* m = d.member(doc, "meshing");
  if (m && d.object(*m, "/meshing", {"max_patch_area", "adaptive", "refine_direct"}))
    decode_meshing(d, *m, scene.meshing, scene.unit_m);
  const json* s = d.member(doc, "solver");
  if (s && d.object(*s, "/solver",
                    {"tolerance", "max_iterations", "method", "accuracy", "exact_visibility"}))
    decode_solver(d, *s, scene.solver);
  const json* o = d.member(doc, "output");
  if (o && d.object(*o, "/output", {"spectral", "per_source", "view_factors", "error_estimate", "ugr_tables"}))
    decode_output(d, *o, scene.output);
}

}  // namespace lambert::codec
