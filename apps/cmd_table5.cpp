// epuck2-fit table5 LOGS...: the paper's Table 5 for these logs. Per discharge model, the average
// MSE of the fitted functions against the logs ("analytic"), of the runtime models run at 10 ticks
// per second over the logged speeds with the fitted tables ("simulated", plug-in compatible
// arithmetic as in the paper's ARGoS runs; the corrected behaviour beside it), with the plug-in's
// published tables, and the paper's published values.
#include <cstdio>
#include <iostream>

#include "app_support.hpp"
#include "battery_input.hpp"
#include "commands.hpp"
#include "log_help.hpp"
#include "epuck2/calibrate/battery.hpp"
#include "epuck2/calibrate/published.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"

namespace epuck2::app {

namespace {
namespace mb = models::battery;

struct Table5Options {
  std::vector<std::string> logs;
  bool json = false;
  std::string output;
  double dt_s = 0.1;
  bool skip_bad_rows = false;
  std::string charge_map;
};

nlohmann::json as_json(const calibrate::ModelMse& m) {
  nlohmann::json j = nlohmann::json::object();
  for (mb::Model model : mb::kAllModels) j[std::string(mb::to_string(model))] = m.get(model);
  return j;
}

int run_table5(const Table5Options& o) {
  const BatteryInput in = read_battery_input("table5", o.logs, o.skip_bad_rows, o.charge_map, false);
  const auto& runs = in.runs;
  const calibrate::BatteryFit f = calibrate::fit_battery(runs);
  report_conversion("table5", in);
  for (const auto& w : in.warnings) std::cerr << "table5: warning: " << w << '\n';
  if (!f.tables) {
    const calibrate::SpeedCoverage c = calibrate::speed_coverage(f);
    std::string why = "table5 needs runs at every speed 0, 1, ..., 15 cm/s (and only those) to build the model tables; these logs cover " +
                      std::to_string(c.covered.size()) + (c.covered.size() == 1 ? " speed: " : " speeds: ") +
                      calibrate::speeds_text(c.covered) +
                      " cm/s; missing: " + calibrate::speeds_text(c.missing) + " cm/s";
    if (!c.other.empty()) why += "; not one of 0..15: " + calibrate::speeds_text(c.other) + " cm/s";
    if (o.json)  // the coverage by value for a program reading standard output; the exit status stays 1
      std::cout << json_text({{"complete", false},
                              {"error", why},
                              {"speeds_covered_cm_s", c.covered},
                              {"speeds_missing_cm_s", c.missing},
                              {"speeds_other_cm_s", c.other}});
    throw NoUsableFit(why);
  }
  const calibrate::ModelMse simulated = calibrate::simulated_mse(runs, *f.tables, mb::Behaviour::argos_compatible, o.dt_s);
  const calibrate::ModelMse corrected = calibrate::simulated_mse(runs, *f.tables, mb::Behaviour::corrected, o.dt_s);
  const calibrate::ModelMse plugin = calibrate::simulated_mse(runs, mb::plugin_tables(), mb::Behaviour::argos_compatible, o.dt_s);
  const calibrate::ModelMse pa = calibrate::paper_table5_analytic();
  const calibrate::ModelMse pg = calibrate::paper_table5_argos();

  nlohmann::json ratio_a = nlohmann::json::object(), ratio_s = nlohmann::json::object();
  for (mb::Model m : mb::kAllModels) {
    ratio_a[std::string(mb::to_string(m))] = f.mse.get(m) / pa.get(m);
    ratio_s[std::string(mb::to_string(m))] = simulated.get(m) / pg.get(m);
  }
  const calibrate::SpeedCoverage coverage = calibrate::speed_coverage(f);
  nlohmann::json j{
      {"complete", true},
      {"speeds_covered_cm_s", coverage.covered},
      {"speeds_missing_cm_s", coverage.missing},
      {"speeds_other_cm_s", coverage.other},
      {"logs", o.logs.size()},
      {"speeds", f.speeds.size()},
      {"tick_s", o.dt_s},
      {"analytic", as_json(f.mse)},
      {"simulated", as_json(simulated)},
      {"simulated_corrected", as_json(corrected)},
      {"plugin_tables_simulated", as_json(plugin)},
      {"published", {{"analytic", as_json(pa)}, {"argos", as_json(pg)}}},
      {"ratio_to_published", {{"analytic", ratio_a}, {"simulated", ratio_s}}},
  };
  if (const nlohmann::json c = conversion_json(in); !c.is_null()) j["charge_conversion"] = c;
  if (in.map && in.conversion.logs > 0) {  // the map that gave the charge of voltage-only logs
    j["charge_map"] = calibrate::charge_map_to_json(*in.map);
    if (!in.map_from_file.empty()) j["charge_map"]["from_file"] = in.map_from_file;
  }
  const std::string text = json_text(j);
  if (!o.output.empty()) {
    write_json(j, o.output);
    std::cerr << "table5: wrote " << o.output << '\n';
  }
  if (o.json) {
    std::cout << text;
    return 0;
  }
  std::printf("Table 5: average MSE (charge units^2) over %zu speeds, %zu logs\n\n", f.speeds.size(), o.logs.size());
  std::printf("%-34s %9s %9s %9s %13s\n", "source", "Simple", "Linear", "Cubic", "Approximated");
  auto row = [](const char* name, const calibrate::ModelMse& m) {
    std::printf("%-34s %9.4f %9.4f %9.4f %13.4f\n", name, m.simple, m.linear, m.cubic, m.approximated);
  };
  row("analytic (fitted to these logs)", f.mse);
  row("paper, analytic", pa);
  row("simulated, fitted tables (ARGoS)", simulated);
  row("paper, ARGoS", pg);
  row("simulated, fitted, corrected", corrected);
  row("simulated, plug-in's tables", plugin);
  std::printf("\nratio analytic/paper:  simple %.2f  linear %.2f  cubic %.2f  approximated %.2f\n",
              f.mse.simple / pa.simple, f.mse.linear / pa.linear, f.mse.cubic / pa.cubic,
              f.mse.approximated / pa.approximated);
  std::printf("ratio simulated/paper: simple %.2f  linear %.2f  cubic %.2f  approximated %.2f\n",
              simulated.simple / pg.simple, simulated.linear / pg.linear, simulated.cubic / pg.cubic,
              simulated.approximated / pg.approximated);
  if (in.conversion.logs > 0)
    std::printf("\nCharge of %zu voltage-only logs from voltage_v through the voltage->charge map %s (residual sd %.3g); "
                "clamped to its range: %zu below, %zu above.\n",
                in.conversion.logs, in.map_from_file.empty() ? "fitted to the logs with both columns" : ("of " + in.map_from_file).c_str(),
                in.map->residual_sd, in.conversion.below_range, in.conversion.above_range);
  return 0;
}
}  // namespace

void setup_table5(CLI::App& app, Action& action) {
  auto o = std::make_shared<Table5Options>();
  CLI::App* sub = app.add_subcommand("table5", "Reproduce the paper's Table 5 (average MSE per discharge model) for these logs");
  sub->add_option("logs", o->logs, "Battery discharge logs covering speeds 0..15 cm/s")->required()->check(CLI::ExistingFile);
  sub->add_flag("--json", o->json, "Print one JSON object instead of the table");
  sub->add_option("-o,--output", o->output, "Also write the JSON report to this file (atomically)")->type_name("FILE")->check(output_file());
  // As simulate's --dt: 1 ms to 10 s (the plug-in ticks at 0.1 s).
  sub->add_option("--dt", o->dt_s, "Simulation tick in seconds")->capture_default_str()->check(finite_range(1e-3, 10.0));
  add_charge_map_option(sub, o->charge_map);
  sub->footer(log_format_footer(logs::Kind::battery,
                                "Optional: voltage_v (logs without charge are converted through the voltage->charge map). One "
                                "speed per run; runs at every speed 0, 1, ..., 15 cm/s are needed."));
  add_skip_bad_rows(sub, o->skip_bad_rows);
  sub->callback([o, &action] { action = [o] { return run_table5(*o); }; });
}

}  // namespace epuck2::app
