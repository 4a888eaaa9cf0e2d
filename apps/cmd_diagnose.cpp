// epuck2-fit diagnose [--kind KIND] [--json] [-o FILE] [--plot FILE] [--progress]
//                    [--battery-model MODEL] [--coefficients plugin|fitted|FILE] [--effects LIST] LOGS...:
// what the plug-in's model (or the base model of a coefficient file) gets wrong on these logs, the
// cause from the catalogue, and the held-out gain of fixing it (docs/diagnose.md). The spellings published before (--json FILE, --json -, --plot DIR) still
// work: main.cpp turns `--json FILE.json` into the hidden --json-file before parsing.
#include <cctype>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <unistd.h>

#include "app_support.hpp"
#include "commands.hpp"
#include "epuck2/models/effects.hpp"
#include "log_help.hpp"
#include "epuck2/calibrate/battery_json.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/calibrate/report_json.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/diagnose/extended_model.hpp"
#include "epuck2/diagnose/report_output.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/plot/diagnosis_figure.hpp"
#include "epuck2/plot/figure.hpp"

namespace epuck2::app {

namespace {

namespace dg = epuck2::diagnose;

struct DiagnoseOptions {
  std::string kind;
  bool json = false;       ///< print the JSON report instead of the human one
  std::string output;      ///< -o: write the JSON report, atomically
  std::string json_file;   ///< the old spelling --json FILE (hidden): the same as -o FILE
  std::string plot;        ///< a figure FILE (.png, .svg, .pdf), or (old spelling) an existing folder
  std::string battery_model = "cubic";
  std::size_t battery_model_given = 0;  ///< --battery-model on the command line (else a file's may set it)
  std::string coefficients;
  std::string robot;    ///< --robot: the --coefficients file's robot set asked for
  std::string effects;  ///< --effects: the search's effects, comma-separated (empty: all)
  std::vector<std::string> logs;
  bool skip_bad_rows = false;
  bool progress = false;
};

/// --effects' list: the names between commas. One value, split here (CLI11's delimiter dropped
/// empty names and let `--effects ,` take the next argument, `-o`, as an effect): an empty name
/// is a usage error.
/// An example of an --effects list for the messages: two ground effects, named by the registry.
std::string example_effects() {
  namespace fx = models::effects;
  return std::string(fx::ground_catalogue()[fx::ground::black_offset].name) + "," +
         fx::ground_catalogue()[fx::ground::white_level].name;
}

std::vector<std::string> effect_list(const std::string& list) {
  std::vector<std::string> names;
  if (list.empty()) return names;
  std::size_t from = 0;
  for (;;) {
    const std::size_t comma = list.find(',', from);
    names.push_back(list.substr(from, comma == std::string::npos ? std::string::npos : comma - from));
    if (names.back().empty())
      throw UsageError("--effects '" + list + "': an empty effect name; give the names between commas, e.g. " + example_effects());
    if (comma == std::string::npos) return names;
    from = comma + 1;
  }
}

/// The base model as it is named in the report: the plug-in's, or FILE's (--coefficients).
std::string base_model_name(const std::string& coefficients, const std::string& robot_set) {
  if (coefficients.empty() || coefficients == "plugin") return "The plug-in's model with the coefficients given";
  if (coefficients == "fitted") return "The plug-in's model with the CLI's compiled-in fitted battery tables";
  if (!robot_set.empty()) return logs::escape_control(coefficients) + "'s model with robot " + robot_set + "'s coefficients (robots." + robot_set + ")";
  return logs::escape_control(coefficients) + "'s model with its coefficients";
}

/// Where --plot draws: FILE itself, or in a folder (the spelling published first) its
/// diagnose_<kind>.png.
std::string figure_path(const std::string& plot, logs::Kind kind) {
  namespace fs = std::filesystem;
  if (!plot.empty() && fs::is_directory(plot))
    return (fs::path(plot) / ("diagnose_" + std::string(logs::to_string(kind)) + ".png")).string();
  return plot;
}

int run_diagnose(const DiagnoseOptions& o) {
  std::optional<logs::Kind> kind;
  if (!o.kind.empty()) {
    kind = logs::parse_kind(o.kind);
    if (!kind) throw UsageError("--kind: " + unknown_name("kind", o.kind, kind_names()));
  }
  if (!o.output.empty() && !o.json_file.empty() && o.output != o.json_file)
    throw UsageError("--json " + o.json_file + " and -o " + o.output +
                     ": both name the file of the JSON report (--json FILE is the old spelling of -o FILE); give one");
  const std::string output = o.output.empty() ? o.json_file : o.output;
  auto logs = read_logs_reporting("diagnose", o.logs, kind, o.skip_bad_rows);
  if (logs.empty()) throw UsageError("no logs given");
  if (!dg::supported(logs.front().kind))
    throw UsageError("diagnose does not support the kind '" + std::string(logs::to_string(logs.front().kind)) +
                     "' yet");
  std::vector<std::string> log_names;
  std::vector<std::string> log_robots;  // the figure's marker per robot
  std::vector<std::string> column_warnings;  // a robot column naming several robots: said, not split
  for (const auto& l : logs) {
    log_names.push_back(l.path);
    log_robots.push_back(l.robot);
    if (std::string w = robot_column_warning(l); !w.empty()) column_warnings.push_back(std::move(w));
  }
  dg::Options options;
  if (!models::battery::parse_model(o.battery_model, options.battery_model))
    throw UsageError("--battery-model: " + unknown_name("discharge model", o.battery_model, {"simple", "linear", "cubic", "approximated"}));
  // The base model from --coefficients (a calibration's or a diagnosis's file, or the fitted
  // battery tables): a diagnosis's battery file also gives its discharge model, unless
  // --battery-model names one, and its capacity scale, from which effects are changes.
  // A calibration of several robots: the logs' robot's own set when the file has one (or
  // --robot's), else the pooled set, said as ARGoS says it (docs/cli.md).
  const coefficients::LogRobotChoice choice = coefficients_robot(o.coefficients, o.robot, log_robots);
  if (!choice.note.empty()) std::cerr << "diagnose: " << choice.note << '\n';
  nlohmann::json file;
  if (const auto base = coefficients_model(std::string(logs::to_string(logs.front().kind)), o.coefficients, &file, choice.robot))
    dg::set_base_model(options, *base, file.contains("battery_model") && o.battery_model_given == 0);
  options.effects = effect_list(o.effects);
  // Progress on standard error (never on standard output, which may hold the JSON report): on a
  // terminal one line rewritten in place, with --progress elsewhere one line per stage.
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  if (o.progress || tty) {
    options.progress = [tty](const dg::Progress& p) {
      std::string line = "diagnose: " + p.stage;
      if (p.total > 0) line += " " + std::to_string(p.done) + "/" + std::to_string(p.total);
      if (!p.detail.empty()) line += " (" + p.detail + ")";
      if (p.step > 0) line += ", search step " + std::to_string(p.step);
      line += "...";
      if (tty) std::fprintf(stderr, "\r%s\033[K", line.c_str());
      else std::fprintf(stderr, "%s\n", line.c_str());
      std::fflush(stderr);
    };
  }
  const dg::ModelInputs inputs = dg::model_inputs(logs, options);  // the covariates' centres, the battery's tables
  dg::Report r = dg::diagnose(std::move(logs), options);  // the logs are released once read
  if (options.progress && tty) std::fprintf(stderr, "\r\033[K");
  if (!r.supported) throw UsageError(r.message);
  // The model's noise is the replicates' where the logs have them: say when the residuals are far
  // from it (misfit the model leaves, which a simulation must not draw as noise).
  for (std::string& w : dg::noise_warnings(r, inputs.replicate_noise)) r.warnings.push_back(std::move(w));
  if (!choice.warning.empty()) r.warnings.push_back(choice.warning);
  r.warnings.insert(r.warnings.end(), column_warnings.begin(), column_warnings.end());
  for (const auto& w : r.warnings) std::fprintf(stderr, "diagnose: warning: %s\n", w.c_str());
  // All or nothing: the JSON report and the figure are renamed into place together, then printed.
  const std::string text = o.json || !output.empty() ? json_text(diagnose::report_json(r, o.logs, inputs)) : std::string();
  const std::string figure = figure_path(o.plot, r.kind);
  logs::OutputStage stage;
  if (!output.empty()) stage.write(output, text);
  if (!figure.empty()) plot::diagnosis_figure(stage, figure, r, log_names, log_robots);
  stage.commit();
  if (!output.empty()) std::cerr << "diagnose: wrote " << output << '\n';
  if (!figure.empty()) std::cerr << "diagnose: drew " << figure << '\n';
  print_figure_warnings("diagnose");
  if (logs::is_standard_output(output)) return 0;  // -o -: the JSON report is standard output, alone
  if (o.json) std::cout << text;
  else std::fputs(diagnose::report_text(r, base_model_name(o.coefficients, choice.robot)).c_str(), stdout);
  return 0;
}

}  // namespace

void setup_diagnose(CLI::App& app, Action& action) {
  auto o = std::make_shared<DiagnoseOptions>();
  CLI::App* sub = app.add_subcommand("diagnose", "What the simulation gets wrong on these logs, why, and what fixing it gains");
  sub->add_option("--kind", o->kind, "Kind of the logs (recognised from the columns when omitted)")
      ->check(one_of(kind_names(), "kind"));
  sub->add_flag("--json", o->json,
                "Print the JSON report instead of the human one (the old spellings --json FILE.json and "
                "--json - still work: the first is -o FILE.json)");
  sub->add_option("-o,--output", o->output, "Write the JSON report to FILE, atomically (-: to standard output, in place of the human report)")->type_name("FILE")->check(output_file());
  sub->add_option("--json-file", o->json_file)->group("")->check(output_file());  // what main.cpp makes of the old --json FILE.json
  sub->add_option("--plot", o->plot,
                  "Draw the residuals before and after the findings, one panel per measured quantity, to FILE "
                  "(.png, .svg or .pdf, by the extension); an existing folder DIR (the old spelling) gets "
                  "DIR/diagnose_<kind>.png")
      ->check(CLI::Validator(
          [](std::string& input) -> std::string {
            const std::string why = plot::why_not_a_figure(input);
            if (why.empty() || std::filesystem::is_directory(input)) return std::string();
            return why + " (or an existing folder, the old spelling: DIR/diagnose_<kind>.png)";
          },
          "{.png,.svg,.pdf}|DIR"))
      ->check(output_file(true))
      ->type_name("FILE");
  add_figure_options(sub);
  CLI::Option* battery_model = sub->add_option(
      "--battery-model", o->battery_model, "battery: the discharge model simulated (default: a diagnosis file's, else cubic)")
      ->capture_default_str()
      ->check(one_of({"simple", "linear", "cubic", "approximated"}, "discharge model"));
  sub->add_option("--coefficients", o->coefficients,
                  "The base model: plugin (the plug-in's published model, default); a coefficient FILE of the logs' kind "
                  "(epuck2-fit KIND -o, or diagnose -o); battery also: fitted (the CLI's compiled-in tables)");
  add_coefficients_robot(sub, o->robot);
  sub->add_option("--effects", o->effects,
                  "Search only these effects of the catalogue, comma-separated (e.g. " + example_effects() + "); default: all")
      ->check(CLI::Validator(
          [](std::string& input) -> std::string {
            if (input.empty()) return "an empty list; give effect names between commas, e.g. " + example_effects();
            return std::string();
          },
          "LIST"))
      ->type_name("LIST");
  sub->add_option("logs", o->logs, "Log files of one kind (CSV, docs/logs.md)")->required()->check(CLI::ExistingFile);
  sub->add_flag("--progress", o->progress,
                "Show progress on standard error (stage, effect being fitted); on by default when standard error is a terminal");
  sub->footer(all_log_formats_footer());
  add_skip_bad_rows(sub, o->skip_bad_rows);
  sub->callback([o, battery_model, &action] {
    o->battery_model_given = battery_model->count();
    action = [o] { return run_diagnose(*o); };
  });
}

}  // namespace epuck2::app
