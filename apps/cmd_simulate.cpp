// epuck2-fit simulate battery --model M [--compat argos|corrected] [--coefficients FILE|plugin|fitted]
//   --profile FILE: runs one discharge model over a speed profile at 10 ticks per second from a
// full charge and prints CSV time_s,charge (charge with 17 significant digits).
// epuck2-fit simulate battery --like LOG [--coefficients FILE|plugin|fitted] [--battery-model M]
//   [--noise --seed N]: the runtime battery model over a measured discharge log's own speeds and
// time steps, written as that log with simulated charge (cmd_simulate_like.cpp's run_like).
#include <cstdio>
#include <iostream>

#include "app_support.hpp"
#include "commands.hpp"
#include "epuck2/calibrate/battery_json.hpp"
#include "epuck2/logs/output.hpp"
#include "epuck2/models/battery_simulation.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/kinds.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"

namespace epuck2::app {

namespace {
namespace mb = models::battery;

// The tick's bounds: the plug-in ticks at 0.1 s; 1 ms already makes ~1e8 rows over a battery's
// life (a few GB of CSV), and past 10 s a tick no longer follows a speed profile, nor is the
// corrected models' step exact (the longest step `simulate --like` takes, lib/models kinds.hpp).
constexpr double kMinTick_s = 1e-3, kMaxTick_s = models::sensors::kBatteryLongestStep_s;

struct SimulateOptions {
  std::string like;  ///< --like LOG: the other mode (run_like); --model and --profile are this one's
  std::string battery_model;
  bool noise = false;
  std::uint64_t seed = 1;
  std::string model;
  std::string compat = "corrected";
  std::string coefficients;
  std::string profile;
  std::string output;
  double dt_s = 0.1;
  bool skip_bad_rows = false;
};

mb::Tables choose_tables(const SimulateOptions& o, bool argos) {
  std::string source = o.coefficients;
  if (source.empty()) source = argos ? "plugin" : "fitted";
  if (source == "plugin") return mb::plugin_tables();
  if (source == "fitted") return std::get<models::sensors::BatteryModel>(*coefficients_model("battery", source)).tables;
  return coefficients::battery_tables_from_json(read_json(coefficient_file(source)), source);
}

int run_simulate(const SimulateOptions& o) {
  if (!o.like.empty()) {
    LikeOptions like;
    like.kind = logs::Kind::battery;
    like.like = o.like;
    like.coefficients = o.coefficients;
    like.battery_model = o.battery_model;
    like.noise = o.noise;
    like.seed = o.seed;
    like.output = o.output;
    like.skip_bad_rows = o.skip_bad_rows;
    return run_like(like);
  }
  if (o.profile.empty()) throw UsageError("--profile is required (or --like LOG: simulate a measured discharge log)");
  if (o.model.empty()) throw UsageError("--model is required with --profile");
  mb::Model model{};
  if (!mb::parse_model(o.model, model))
    throw UsageError("--model: " + unknown_name("discharge model", o.model, {"simple", "linear", "cubic", "approximated"}));
  const bool argos = o.compat == "argos";
  const mb::Tables tables = choose_tables(o, argos);
  logs::ReadOptions read_options;
  read_options.skip_bad_rows = o.skip_bad_rows;
  const logs::Log profile_log = logs::read_table(o.profile, {"time_s", "speed_cm_s"}, read_options);
  report_skipped("simulate", {profile_log});
  std::vector<mb::ProfilePoint> profile;
  const auto& t = profile_log.col("time_s");
  const auto& v = profile_log.col("speed_cm_s");
  for (std::size_t i = 0; i < t.size(); ++i) profile.push_back({t[i], std::abs(v[i])});
  std::vector<mb::ChargeSample> samples;
  try {
    samples = mb::simulate_discharge(model, argos ? mb::Behaviour::argos_compatible : mb::Behaviour::corrected, tables,
                                     profile, o.dt_s, 1.0);
  } catch (const std::invalid_argument& e) {
    throw UsageError("--profile " + o.profile + " with --dt " + logs::format_number(o.dt_s) + ": " + e.what());
  }
  std::string csv = "time_s,charge\n";
  csv.reserve(samples.size() * 32);
  char line[96];
  for (const auto& s : samples) {
    std::snprintf(line, sizeof line, "%.10g,%.17g\n", s.time_s, s.charge);
    csv += line;
  }
  write_output(csv, o.output);
  if (!o.output.empty()) std::cerr << "simulate: wrote " << o.output << '\n';
  return 0;
}
}  // namespace

void setup_simulate(CLI::App& app, Action& action) {
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* sim = app.add_subcommand("simulate", "Run a runtime model: `simulate battery` over a speed profile, `simulate KIND --like LOG` on a measured log's conditions");
  sim->require_subcommand(1);
  CLI::App* sub = sim->add_subcommand(
      "battery", "Run a discharge model over a speed profile from a full charge, or (--like) over a measured discharge log");
  CLI::Option* model = sub->add_option("--model", o->model, "The discharge model (with --profile; required there)")
                           ->check(one_of({"simple", "linear", "cubic", "approximated"}, "discharge model"));
  CLI::Option* compat =
      sub->add_option("--compat", o->compat,
                      "argos: the E-Puck2 plug-in's arithmetic to the last bit, quirks included (and ARGoS's "
                      "one-tick command delay and 0.9/0.1 first tick after a change); corrected: the project's "
                      "corrected behaviour (docs/battery-models.md)")
          ->capture_default_str()
          ->check(one_of({"argos", "corrected"}, "behaviour"));
  sub->add_option("--coefficients", o->coefficients,
                  "Coefficient file (JSON from `epuck2-fit battery -o`, or with --like a battery `diagnose -o` report: "
                  "tables, discharge model, " + std::string(models::effects::battery_catalogue()[models::effects::battery::capacity_scale].name) +
                      ", noise), or `plugin` (the plug-in's published "
                  "tables), or `fitted` (the compiled-in data/fitted tables). Default: plugin with --compat argos "
                  "or --like, else fitted");
  CLI::Option* profile =
      sub->add_option("--profile", o->profile,
                      "CSV with columns time_s,speed_cm_s (a command holds until the next row; docs/logs.md#speed-profile-for-simulate-battery); "
                      "required unless --like")
          ->check(CLI::ExistingFile);
  CLI::Option* dt = sub->add_option("--dt", o->dt_s, "Tick in seconds (with --profile)")->capture_default_str()->check(finite_range(kMinTick_s, kMaxTick_s));
  CLI::Option* like =
      sub->add_option("--like", o->like,
                      "A measured discharge log (docs/logs.md, with `charge`): run the corrected model with its capacity "
                      "scale over the log's own speeds and time steps from its first charge, and write the log with "
                      "simulated charge")
          ->check(CLI::ExistingFile);
  CLI::Option* battery_model =
      sub->add_option("--battery-model", o->battery_model,
                      "With --like: the discharge model (default: the --coefficients report's, else cubic)")
          ->check(one_of({"simple", "linear", "cubic", "approximated"}, "discharge model"));
  CLI::Option* noise = sub->add_flag("--noise", o->noise, "With --like: add the file's charge noise (Gaussian, its `noise` section)");
  CLI::Option* seed = sub->add_option("--seed", o->seed, "With --like: seed of the noise")->capture_default_str();
  for (CLI::Option* profile_only : {model, compat, profile, dt}) like->excludes(profile_only);
  for (CLI::Option* like_only : {battery_model, noise, seed}) like_only->needs(like);
  add_skip_bad_rows(sub, o->skip_bad_rows);
  sub->add_option("-o,--output", o->output, "Write the CSV to this file (atomically) instead of standard output")->type_name("FILE")->check(output_file());
  sub->callback([o, &action] { action = [o] { return run_simulate(*o); }; });
  setup_simulate_like(*sim, action);
}

}  // namespace epuck2::app
