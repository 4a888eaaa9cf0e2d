// epuck2-fit table5 LOGS...: the paper's Table 5 for these logs. Per discharge model, the average
// MSE of the fitted functions against the logs ("analytic"), of the runtime models run at 10 ticks
// per second over the logged speeds with the fitted tables ("simulated", plug-in compatible
// arithmetic as in the paper's ARGoS runs; the corrected behaviour beside it), with the plug-in's
// published tables, and the paper's published values.
#include <cstdio>
#include <iostream>

#include "app_support.hpp"
#include "battery_input.hpp"
#include "epuck2/calibrate/battery_report.hpp"
#include "commands.hpp"
#include "log_help.hpp"
#include "epuck2/calibrate/battery.hpp"

namespace epuck2::app {

namespace {

struct Table5Options {
  std::vector<std::string> logs;
  bool json = false;
  std::string output;
  double dt_s = 0.1;
  bool skip_bad_rows = false;
  std::string charge_map;
};

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
  const calibrate::Table5 t = calibrate::table5(runs, f, o.logs.size(), o.dt_s);
  nlohmann::json j = calibrate::table5_json(t);
  if (const nlohmann::json c = calibrate::charge_conversion_json(in.conversion, in.map_from_file); !c.is_null()) j["charge_conversion"] = c;
  if (in.map && in.conversion.logs > 0) {  // the map that gave the charge of voltage-only logs
    j["charge_map"] = calibrate::charge_map_to_json(*in.map);
    if (!in.map_from_file.empty()) j["charge_map"]["from_file"] = in.map_from_file;
  }
  const std::string text = json_text(j);
  if (!o.output.empty()) {
    write_json(j, o.output);
    std::cerr << "table5: wrote " << o.output << '\n';
  }
  if (logs::is_standard_output(o.output)) return 0;  // -o -: the JSON report is standard output, alone
  if (o.json) {
    std::cout << text;
    return 0;
  }
  std::fputs(calibrate::table5_text(t).c_str(), stdout);
  if (in.map) std::fputs(calibrate::charge_conversion_text(in.conversion, in.map_from_file, in.map->residual_sd).c_str(), stdout);
  return 0;
}
}  // namespace

void setup_table5(CLI::App& app, Action& action) {
  auto o = std::make_shared<Table5Options>();
  CLI::App* sub = app.add_subcommand("table5", "Reproduce the paper's Table 5 (average MSE per discharge model) for these logs");
  sub->add_option("logs", o->logs, "Battery discharge logs covering speeds 0..15 cm/s")->required()->check(CLI::ExistingFile);
  sub->add_flag("--json", o->json, "Print one JSON object instead of the table");
  sub->add_option("-o,--output", o->output, "Also write the JSON report to this file (atomically; -: to standard output, in place of the table)")->type_name("FILE")->check(output_file());
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
