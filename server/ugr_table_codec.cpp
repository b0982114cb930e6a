#include "server/ugr_table_codec.h"

#include <cstdio>

namespace lambert {

using nlohmann::json;

json ugr_table_json(const std::optional<UgrTable>& table) {
  if (!table) return nullptr;
  json rooms = json::array(), reflectances = json::array(), crosswise = json::array(), endwise = json::array();
  for (const UgrRoom& r : ugr_rooms()) rooms.push_back({r.x_h, r.y_h});
  for (const UgrReflectances& r : ugr_reflectances()) reflectances.push_back({r.ceiling, r.walls, r.plane});
  auto row = [](const auto& cells) {
    json out = json::array();
    for (const std::optional<double>& v : cells) out.push_back(v ? json(*v) : json(nullptr));
    return out;
  };
  for (std::size_t k = 0; k < kUgrRooms; ++k) {
    crosswise.push_back(row(table->crosswise[k]));
    endwise.push_back(row(table->endwise[k]));
  }
  return {{"method", "CIE 190:2010"},
          {"H_m", kUgrHeight_m},
          {"spacing_to_height", kUgrSpacingToHeight},
          {"luminous_flux_lm", table->luminous_flux_lm},
          {"rooms", std::move(rooms)},
          {"reflectances", std::move(reflectances)},
          {"crosswise", std::move(crosswise)},
          {"endwise", std::move(endwise)}};
}

std::string ugr_table_text(const UgrTable& table) {
  char line[160];
  std::string out = "UGR table, CIE 190:2010: H = 2 m above the eye, S = 0.25 H, luminous flux ";
  std::snprintf(line, sizeof line, "%.1f lm\n", table.luminous_flux_lm);
  out += line;
  out += "reflectances ceiling/walls/plane:\n";
  std::string head = "  X     Y   |";
  for (int view = 0; view < 2; ++view)
    for (const UgrReflectances& r : ugr_reflectances()) {
      std::snprintf(line, sizeof line, " %2.0f/%2.0f/%2.0f", r.ceiling * 100, r.walls * 100, r.plane * 100);
      head += line;
    }
  out += "            |" + std::string(22, ' ') + "crosswise" + std::string(39, ' ') + "endwise\n" + head + "\n";
  auto cell = [&](const std::optional<double>& v) {
    if (v) std::snprintf(line, sizeof line, " %8.1f", *v);
    else std::snprintf(line, sizeof line, " %8s", "-");
    return std::string(line);
  };
  for (std::size_t k = 0; k < kUgrRooms; ++k) {
    std::snprintf(line, sizeof line, "%3dH  %3dH  |", ugr_rooms()[k].x_h, ugr_rooms()[k].y_h);
    std::string row = line;
    for (const auto& v : table.crosswise[k]) row += cell(v);
    for (const auto& v : table.endwise[k]) row += cell(v);
    out += row + "\n";
  }
  return out;
}

}  // namespace lambert
