// The C++ side of tests/viewer_scale_test.mjs: reads cases (JSON) on standard input and answers
// them with server/colour_scale.h and server/isolines.h, which draw the PNG legends and grid maps,
// so that the test can hold the browser viewer's JavaScript copies to the same answers.
//   in:  {"scales": [{"values": [...], "kind": "log"|"linear", "max_ticks": [..]}],
//         "labels": [...], "ramp": [...], "isolines": [{"values": [...], "nu", "nv", "level"}]}
//   out: {"scales": [{"lo", "hi", "positions": [...], "ticks": [[{"value", "label"}...]...]}],
//         "labels": [...], "ramp": [[r, g, b]...], "isolines": [[[x0, y0, x1, y1]...]...]}
#include <iostream>
#include <nlohmann/json.hpp>

#include "server/colour_scale.h"
#include "server/isolines.h"

namespace {

using json = nlohmann::json;
using namespace lambert;

json answer_scale(const json& in) {
  const std::vector<double> values = in["values"].get<std::vector<double>>();
  const ScaleKind kind = in["kind"] == "log" ? ScaleKind::Log : ScaleKind::Linear;
  const ColourScale scale = colour_scale(values, kind);
  json out = {{"lo", scale.lo}, {"hi", scale.hi}, {"positions", json::array()}, {"ticks", json::array()}};
  for (double v : values) out["positions"].push_back(scale.position(v));
  for (int max_ticks : in["max_ticks"].get<std::vector<int>>()) {
    json ticks = json::array();
    for (const Tick& t : scale_ticks(scale, max_ticks)) ticks.push_back({{"value", t.value}, {"label", t.label}});
    out["ticks"].push_back(ticks);
  }
  return out;
}

json answer_isolines(const json& in) {
  json out = json::array();
  for (const Segment2& s : isolines(in["values"].get<std::vector<double>>(), in["nu"], in["nv"], in["level"]))
    out.push_back({s.a.x, s.a.y, s.b.x, s.b.y});
  return out;
}

}  // namespace

int main() {
  const json in = json::parse(std::cin);
  json out = {{"scales", json::array()}, {"labels", json::array()}, {"ramp", json::array()}, {"isolines", json::array()}};
  for (const json& s : in["scales"]) out["scales"].push_back(answer_scale(s));
  for (const json& v : in["labels"]) out["labels"].push_back(tick_label(v.get<double>()));
  for (const json& t : in["ramp"]) {
    const Rgb c = false_colour_ramp(t.get<double>());
    out["ramp"].push_back({c.r, c.g, c.b});
  }
  for (const json& g : in["isolines"]) out["isolines"].push_back(answer_isolines(g));
  std::cout << out.dump() << "\n";
}
