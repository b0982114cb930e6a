// The evaluations of a result as JSON (see evaluation_codec.h and SPEC §5).
#include "server/evaluation_codec.h"

#include "solver/task_summary.h"

namespace lambert {
namespace {

using nlohmann::json;

json room_surface_json(const std::optional<RoomSurfaceCheck>& c) {
  if (!c) return nullptr;
  return {{"area_m2", c->area_m2}, {"Em_lx", c->mean_lx}, {"Emin_lx", c->min_lx}, {"Emax_lx", c->max_lx}, {"U0", c->u0}};
}

json task_summary_json(const TaskSummary& t) {
  json grids = json::array();
  for (const GridCheck& g : t.grids)
    grids.push_back({{"name", g.name},
                     {"quantity", quantity_name(g.quantity)},
                     {"points", g.points},
                     {"Em_lx", g.mean_lx},
                     {"Emin_lx", g.min_lx},
                     {"Emax_lx", g.max_lx},
                     {"U0", g.u0},
                     {"Ud", g.ud}});
  return {{"maintenance_factor", t.maintenance_factor},
          {"identified_by", t.by_role ? "role" : "orientation"},
          {"grids", std::move(grids)},
          {"walls", room_surface_json(t.walls)},
          {"ceiling", room_surface_json(t.ceiling)},
          {"floor", room_surface_json(t.floor)}};
}

json glare_json(const GlareResult& g) {
  json sources = json::array();
  for (const GlareSource& s : g.sources) {
    json j = {{"source", s.source},
              {"small", s.small},
              {"luminance_cd_m2", s.luminance_cd_m2},
              {"solid_angle_sr", s.solid_angle_sr},
              {"position_index", s.position_index},
              {"term", s.term}};
    if (s.small) j["intensity_cd"] = s.intensity_cd, j["distance_m"] = s.distance_m;
    sources.push_back(std::move(j));
  }
  return {{"name", g.name},
          {"ugr", g.ugr ? json(*g.ugr) : json(nullptr)},
          {"background_luminance_cd_m2", g.background_luminance_cd_m2},
          {"indirect_illuminance_lx", g.indirect_illuminance_lx},
          {"sources", std::move(sources)}};
}

}  // namespace

void write_evaluations(json& out, const Scene& scene, const Solution& sol, const Report& report) {
  if (const auto summary = make_task_summary(scene, sol, report)) out["task_summary"] = task_summary_json(*summary);
  if (!sol.glare.empty()) {
    json glare = json::array();
    for (const GlareResult& g : sol.glare) glare.push_back(glare_json(g));
    out["glare"] = std::move(glare);
  }
}

}  // namespace lambert
