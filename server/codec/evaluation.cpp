// The evaluations a lighting designer asks of a solution (SPEC §5): "task_summary", EN 12464-1's
// checks of named grids and of the walls and ceiling, and "glare", the observers whose UGR is wanted.
// Read after the probes, whose grids the summary names.
#include <map>

#include "server/codec/sections.h"

namespace lambert::codec {
namespace {

void decode_task_summary(Decoder& d, const json& j) {
  const std::string p = "/task_summary";
  if (!d.object(j, p, {"maintenance_factor", "up", "grids"})) return;
  TaskSummaryOptions options;
  bool ok = true;
  if (const json* m = d.member(j, "maintenance_factor")) {
    const auto v = d.number_in(*m, p + "/maintenance_factor", 0, false, 1, true);
    if (v) options.maintenance_factor = *v;
    else ok = false;
  }
  if (const json* u = d.member(j, "up")) {
    options.up = d.direction(*u, p + "/up");
    ok = ok && options.up.has_value();
  }
  const std::vector<Probe>& probes = d.scene().probes;
  if (const json* g = d.member(j, "grids")) {
    if (!d.array(*g, p + "/grids")) return;
    // Looked up once, not per entry: a scene may list 10⁵ names against 10⁵ probes.
    std::map<std::string_view, int> by_name;
    std::vector<std::string_view> grid_names;
    for (std::size_t k = 0; k < probes.size(); ++k) {
      by_name.emplace(probes[k].name, static_cast<int>(k));
      if (probes[k].is_grid) grid_names.push_back(probes[k].name);
    }
    for (std::size_t i = 0; i < g->size(); ++i) {
      const std::string pi = index_ptr(p + "/grids", i);
      const auto name = d.string((*g)[i], pi);
      if (!name) {
        ok = false;
        continue;
      }
      const auto it = by_name.find(*name);
      const int found = it == by_name.end() ? -1 : it->second;
      if (found < 0 || !probes[found].is_grid) {
        d.error(pi, (found < 0 ? "no probe is named " : "probe " + quote_text(*name) + " is a point, not a grid; ") +
                        (found < 0 ? quote_text(*name) : std::string("the summary takes grids")) +
                        (d.listing() ? suggestion(*name, grid_names) : ""));
        ok = false;
      } else {
        options.grids.push_back(found);
      }
    }
  } else {
    for (std::size_t k = 0; k < probes.size(); ++k)
      if (probes[k].is_grid) options.grids.push_back(static_cast<int>(k));
  }
  const bool any_role = std::any_of(d.scene().surfaces.begin(), d.scene().surfaces.end(),
                                    [](const Surface& s) { return s.role != SurfaceRole::None; });
  if (!any_role && !options.up && !j.contains("up")) {
    d.error(p, "no surface has a role (wall, ceiling, floor): give up, the direction the orientation rule "
               "tells walls from ceilings by");
    ok = false;
  }
  if (ok) d.scene().task_summary = options;
}

void decode_observer(Decoder& d, const json& j, std::size_t i, std::map<std::string, std::string>& names) {
  const std::string p = index_ptr("/glare", i);
  if (!d.object(j, p, {"name", "position", "view", "up"})) return;
  GlareObserver o;
  o.name = d.unique_name(j, p, "observer" + std::to_string(i), names, "an observer");
  const json* jp = d.required(j, p, "position");
  const json* jv = d.required(j, p, "view");
  const json* ju = d.required(j, p, "up");
  std::optional<Point3> position;
  std::optional<Vector3> view, up;
  if (jp) position = d.point(*jp, p + "/position");
  if (jv) view = d.direction(*jv, p + "/view");
  if (ju) up = d.direction(*ju, p + "/up");
  if (!position || !view || !up) return;
  // The camera convention: up need not be perpendicular to the view; its part across it is the
  // vertical of the observer's field (the Guth index's vertical plane).
  const Vector3 across = *up - *view * dot(*up, *view);
  if (length(across) < 1e-6) {
    d.error(p + "/up", "must not be parallel to view");
    return;
  }
  o.position = d.metres(*position);
  o.view = *view;
  o.up = normalize(across);
  d.scene().glare.push_back(std::move(o));
}

}  // namespace

void decode_evaluations(Decoder& d, const json& doc) {
  if (const json* t = d.member(doc, "task_summary")) decode_task_summary(d, *t);
  const json* glare = d.member(doc, "glare");
  if (!glare || !d.array(*glare, "/glare")) return;
  std::map<std::string, std::string> names;
  for (std::size_t i = 0; i < glare->size(); ++i) decode_observer(d, (*glare)[i], i, names);
}

}  // namespace lambert::codec
