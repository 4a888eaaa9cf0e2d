// Writes the E-Puck2 plug-in's own battery tables (epuck2::models::battery::plugin_tables(), its
// verbatim coefficients) as a battery coefficient file, so that the calibrated discharge model with
// behaviour="argos" can be compared bit for bit with the plug-in's own models in ARGoS.
//   usage: argos_plugin_battery_json OUT.json
#include <cstdio>
#include <fstream>
#include <iomanip>

#include <nlohmann/json.hpp>

#include <epuck2/models/plugin_battery_tables.hpp>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.json\n", argv[0]);
    return 2;
  }
  namespace mb = epuck2::models::battery;
  const mb::Tables& t = mb::plugin_tables();
  nlohmann::json j;
  j["kind"] = "battery";
  j["sources"] = {"the E-Puck2 ARGoS plug-in's tables (commit 0c30e1e), verbatim"};
  for (int s = 0; s < mb::kSpeedCount; ++s) {
    nlohmann::json e;
    e["speed_cm_s"] = s;
    e["cubic"] = {t.cubic[s].d, t.cubic[s].c, t.cubic[s].b, t.cubic[s].a};
    e["lifetime_s"] = t.cubic[s].end_s;
    e["linear_slope"] = t.linear_slope_per_s[s];
    for (const auto& g : t.segments[s])
      e["segments"].push_back({{"h", g.h}, {"m", g.m}, {"x1_s", g.x1_s}, {"x2_s", g.x2_s}, {"y1", g.y1}, {"y2", g.y2}});
    j["speeds"].push_back(e);
  }
  j["simple"] = {{"static_slope_per_s", t.simple_static_slope_per_s}, {"moving_slope_per_s", t.simple_moving_slope_per_s}};
  std::ofstream(argv[1]) << std::setprecision(17) << j.dump(2) << '\n';
  return 0;
}
