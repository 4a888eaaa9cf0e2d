// epuck2-fit simulate {proximity,light,ground,camera,drive} --like LOG [--coefficients FILE]
//                     [--noise] [--seed N] [-o FILE]
// epuck2-fit simulate battery --like LOG [--coefficients FILE] [--battery-model M] ... (the
//                     battery subcommand is cmd_simulate.cpp's; its --like runs here)
// Runs the runtime model library (lib/models simulate_log.hpp) on the conditions of a measured log
// (distances and sensors, intensities, grey levels, LED positions, commands and the obstacle's
// distance, a discharge run's speeds and times) and writes a log in the same format with the
// simulated readings in place of the measured ones: comparable row by row. Without
// --coefficients, the plug-in's published model. A model's `covariate:NAME` effects read the
// log's column NAME.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "app_support.hpp"
#include "commands.hpp"
#include "epuck2/models/kind_facts.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/logs/output.hpp"
#include "epuck2/models/kinds.hpp"
#include "epuck2/models/simulate_log.hpp"

namespace epuck2::app {
namespace {

namespace s = models::sensors;

/// The kind's facts (lib/models kind_facts.hpp).
const models::KindFacts& facts_of(logs::Kind kind) { return *models::kind_facts(std::string(logs::to_string(kind))); }

bool contains(const std::vector<const char*>& names, const std::string& name) {
  return std::any_of(names.begin(), names.end(), [&](const char* n) { return name == n; });
}

/// The model's covariate effects' sum on each row, from the log's columns (a usage error naming
/// the column when the log lacks one).
std::vector<double> covariate_offsets(const std::vector<s::CovariateEffect>& covariates, const logs::Log& log,
                                      const LikeOptions& o) {
  for (const auto& c : covariates)
    if (!log.has(c.column))
      throw UsageError("--like " + o.like + ": the model's covariate:" + c.column + " effect reads the column '" + c.column +
                       "', which this log does not have as a numeric column");
  std::vector<double> out(log.rows(), 0.0);
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = s::covariate_offset(covariates, [&](const std::string& column) { return log.col(column)[i]; });
  return out;
}

/// The model: the plug-in's published one without --coefficients (or with `plugin`), the
/// compiled-in fitted one with `fitted`, else the file's (base, effects, noise; a battery file's
/// tables and discharge model); --battery-model, when given, names the discharge model.
coefficients::AnyModel load(const LikeOptions& o) {
  const std::string kind(logs::to_string(o.kind));
  coefficients::AnyModel m = coefficients::plugin_model(kind);
  if (const auto given = coefficients_model(kind, o.coefficients, nullptr, o.robot_set)) m = *given;
  if (!o.battery_model.empty()) {
    auto* battery = std::get_if<s::BatteryModel>(&m);
    if (battery == nullptr || !models::battery::parse_model(o.battery_model, battery->model))
      throw UsageError("--battery-model: " + unknown_name("discharge model", o.battery_model, {"simple", "linear", "cubic", "approximated"}));
  }
  return m;
}

/// Per row, the simulated readings of the kind's reading columns (KindFacts::readings' order): the
/// model's overload of lib/models simulate_log.hpp.
std::vector<std::vector<double>> simulate(const LikeOptions& o, const logs::Log& log, s::StandardNormal& normal) {
  // The columns the simulation reads that the log reader lets a log go without (a battery log's
  // charge, where it has voltage_v instead).
  const models::KindFacts& facts = facts_of(log.kind);
  for (const char* c : facts.columns)
    if (!log.has(c))
      throw UsageError("--like " + o.like + ": a " + facts.name + " log with a '" + c + "' column is needed (this one has none)" +
                       (contains(facts.readings, c) ? "; the run starts from its first reading" : ""));
  return std::visit(
      [&](const auto& m) { return s::simulated_readings(m, log, covariate_offsets(m.covariates, log, o), o.noise, normal); },
      load(o));
}

}  // namespace

int run_like(const LikeOptions& given) {
  const auto logs = read_logs_reporting("simulate", {given.like}, given.kind, given.skip_bad_rows);
  const logs::Log& log = logs.front();
  // A calibration of several robots: the log's robot's own set when the file has one (or
  // --robot's), else the pooled set, said as ARGoS says it (docs/cli.md).
  LikeOptions o = given;
  const coefficients::LogRobotChoice choice = coefficients_robot(o.coefficients, o.robot, {log.robot});
  o.robot_set = choice.robot;
  if (!choice.note.empty()) std::cerr << "simulate: " << logs::escape_control(choice.note) << '\n';
  if (!choice.warning.empty()) std::cerr << "simulate: warning: " << logs::escape_control(choice.warning) << '\n';
  s::StandardNormal normal(o.seed);
  const auto simulated = simulate(o, log, normal);
  const auto& readings = facts_of(log.kind).readings;
  const std::vector<std::string> replaced(readings.begin(), readings.end());
  // A row the sensor does not report (a camera LED whose image falls off the image, which ARGoS
  // drops too) is left out and said: the log format has no "not seen", and a reading off the image
  // is one the log reader refuses.
  std::size_t unseen = 0;
  std::size_t first_unseen = 0;
  for (std::size_t i = 0; i < simulated.size(); ++i)
    if (simulated[i].empty() && unseen++ == 0) first_unseen = i;
  if (unseen > 0 && unseen == simulated.size())
    throw logs::InputError(o.like, log.line_of_row[first_unseen], log.column_of(first_unseen, replaced.front()),
                           "the model sees no row of this log (" + std::to_string(unseen) + " of " + std::to_string(unseen) +
                               " left out: each LED's image falls off the camera's image" +
                               (o.coefficients.empty() ? std::string() : " with " + o.coefficients) +
                               "); nothing was written");
  if (unseen > 0)
    std::cerr << "simulate: " << unseen << " of " << simulated.size() << " rows left out: the model does not see them "
              << "(the LED's image falls off the camera's image, where ARGoS reports no blob); the first at "
              << logs::escape_control(o.like) << ':' << log.line_of_row[first_unseen] << '\n';
  // A NaN or infinite reading is never written: the row's conditions (which the log reader's ranges
  // should have refused) or the model's coefficients overflow the model there.
  for (std::size_t i = 0; i < simulated.size(); ++i)
    for (std::size_t c = 0; c < simulated[i].size(); ++c)
      if (!std::isfinite(simulated[i][c]))
        throw logs::InputError(o.like, log.line_of_row[i], log.column_of(i, replaced[c]),
                               "the simulated " + replaced[c] + " is " + logs::format_number(simulated[i][c]) +
                                   " (the model overflows on this row's conditions" +
                                   (o.coefficients.empty() ? std::string() : " with " + o.coefficients) + "); nothing was written");
  // --noise with a model that has no reading noise (the plug-in's battery, a file whose noise sd are
  // 0): said, and the output not called noisy. Judged by what it does: the same rows without noise.
  bool noisy = o.noise;
  if (o.noise) {
    LikeOptions quiet = o;
    quiet.noise = false;
    s::StandardNormal unused(o.seed);
    if (simulate(quiet, log, unused) == simulated) {
      noisy = false;
      std::cerr << "simulate: --noise: the model has no reading noise (its noise sd is 0): no reading changed; written "
                   "without noise and without a seed\n";
    }
  }
  std::vector<std::string> columns;
  std::size_t text_columns = 0;
  for (const auto& c : log.columns) {
    // A reading the model does not simulate (a battery log's voltage_v): beside the simulated
    // readings it would contradict them.
    if (contains(facts_of(log.kind).not_simulated, c)) continue;
    if (log.has(c)) columns.push_back(c);
    else ++text_columns;
  }
  if (text_columns > 0)
    std::fprintf(stderr, "simulate: text columns of %s are not copied (only numeric columns are)\n", o.like.c_str());
  logs::LogWriter w(columns);
  const std::string model = o.coefficients.empty() || o.coefficients == "plugin" ? std::string(" with the plug-in's published model")
                                                                                 : " with " + o.coefficients +
                                                                                       (o.robot_set.empty() ? std::string() : "'s set robots." + o.robot_set);
  w.comment("Simulated by epuck2-fit simulate " + std::string(logs::to_string(log.kind)) + " --like " + o.like + model +
            (noisy ? " and reading noise, seed " + std::to_string(o.seed)
                   : std::string(o.noise ? ", without noise (--noise given, but the model has none)" : ", without noise")));
  // The log's conditions are the simulation's too (robot, obstacle distance), but its seed is the
  // recording's: the simulation's own replaces it (with --noise), or none is written.
  for (const auto& [k, v] : log.metadata)
    if (k != "seed") w.metadata(k, v);
  // A robot named by a `robot` column (no `# robot:` line) is the log's robot too: written as
  // `# robot:`, since the column is not copied. Every reader takes the column's first cell for the
  // whole file (docs/logs.md: one file, one robot); other names in the column are said, not kept.
  const auto robot_column = log.text.find("robot");
  if (!log.metadata.count("robot") && robot_column != log.text.end() && !robot_column->second.empty()) {
    w.metadata("robot", log.robot);
    std::vector<std::string> others;
    for (const std::string& r : robot_column->second)
      if (r != robot_column->second.front() && std::find(others.begin(), others.end(), r) == others.end()) others.push_back(r);
    if (!others.empty())
      std::cerr << "simulate: the robot column of " << logs::escape_control(o.like) << " names " << others.size() + 1
                << " robots; the log is robot " << logs::escape_control(log.robot)
                << " (its first row's: one file, one robot, docs/logs.md), written as # robot: " << logs::escape_control(log.robot)
                << "; the other names are not kept\n";
  }
  if (noisy) w.metadata("seed", std::to_string(o.seed));
  for (std::size_t i = 0; i < log.rows(); ++i) {
    if (simulated[i].empty()) continue;  // not seen (above)
    std::vector<double> row;
    for (const auto& c : columns) {
      const auto at = std::find(replaced.begin(), replaced.end(), c);
      row.push_back(at == replaced.end() ? log.col(c)[i] : simulated[i][static_cast<std::size_t>(at - replaced.begin())]);
    }
    w.row(row);
  }
  write_output(w.str(), o.output);
  if (!o.output.empty()) std::cerr << "simulate: wrote " << o.output << '\n';
  return 0;
}


void setup_simulate_like(CLI::App& sim, Action& action) {
  for (logs::Kind kind : {logs::Kind::proximity, logs::Kind::light, logs::Kind::ground, logs::Kind::camera, logs::Kind::drive}) {
    auto o = std::make_shared<LikeOptions>();
    o->kind = kind;
    const std::string name(logs::to_string(kind));
    CLI::App* sub = sim.add_subcommand(
        name, "Run the " + name + " model on a measured log's conditions and write the same log with simulated readings");
    sub->add_option("--like", o->like, "The measured " + name + " log (docs/logs.md) whose conditions are simulated")
        ->required()
        ->check(CLI::ExistingFile);
    sub->add_option("--coefficients", o->coefficients,
                    "Coefficient file (`epuck2-fit " + name + " -o` or `diagnose -o`: base, effects, noise); "
                    "default: the plug-in's published model")
        ->check(CLI::ExistingFile);
    add_coefficients_robot(sub, o->robot);
    sub->add_flag("--noise", o->noise, "Add the file's reading noise (Gaussian, its `noise` section)");
    sub->add_option("--seed", o->seed, "Seed of the noise")->capture_default_str();
    sub->add_option("-o,--output", o->output, "Write the log to this file (atomically) instead of standard output")
        ->type_name("FILE")
        ->check(output_file());
    add_skip_bad_rows(sub, o->skip_bad_rows);
    sub->callback([o, &action] { action = [o] { return run_like(*o); }; });
  }
}

}  // namespace epuck2::app
