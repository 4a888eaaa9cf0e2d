// epuck2-fit diagnose [--kind KIND] [--json] [-o FILE] [--plot FILE] LOGS...: what the plug-in's
// model gets wrong on these logs, the cause from the catalogue, and the held-out gain of fixing it
// (docs/diagnose.md). The spellings published before (--json FILE, --json -, --plot DIR) still
// work: main.cpp turns `--json FILE.json` into the hidden --json-file before parsing.
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <unistd.h>

#include "app_support.hpp"
#include "commands.hpp"
#include "log_help.hpp"
#include "epuck2/calibrate/battery_json.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/diagnose/extended_model.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"
#if __has_include("epuck2/fitted/coefficients.hpp")
#include "epuck2/fitted/coefficients.hpp"  // the CLI's `--coefficients fitted` (epuck2::fitted)
#endif
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
  std::string coefficients;
  std::vector<std::string> logs;
  bool skip_bad_rows = false;
  bool progress = false;
};

std::string units(logs::Kind k) {
  switch (k) {
    case logs::Kind::camera: return "px^2";
    case logs::Kind::drive: return "mm^2 (ToF)";
    case logs::Kind::battery: return "charge^2";
    default: return "counts^2";
  }
}

/// What a cause means, in plain words.
std::string meaning(const std::string& cause) {
  static const std::map<std::string, std::string> m{
      {"black_offset", "black still reflects: readings over black sit above 0"},
      {"white_level", "white reads a different level than the model's full scale"},
      {"sensor_gain", "the sensors disagree: each has its own gain"},
      {"nonlinear_response", "the reading is not proportional to the grey level"},
      {"ambient_offset", "ambient light shifts every reading by the same amount"},
      {"long_tail", "the sensor still responds beyond the model's cut-off"},
      {"incidence_angle", "readings fall as the surface tilts away from the sensor"},
      {"saturation", "readings saturate below full scale"},
      {"falloff_exponent", "the reading does not fall with the square of the distance"},
      {"principal_offset", "the optical axis is off the image centre"},
      {"radial_distortion", "the lens bends points away from (or towards) the centre"},
      {"speed_limit", "the wheels do not turn faster than a limit, whatever the command"},
      {"accel_limit", "the wheels reach a new command only gradually: their acceleration is limited"},
      {"wheel_slip", "the robot's speed over the ground trails the wheels while it accelerates"},
      {"speed_scale", "the robot covers a different distance than its wheels turn (worn or mis-sized wheels)"},
      {"latency", "the ToF reading describes an earlier moment than its time stamp"},
      {"tof_offset", "the ToF reads a constant amount off at every range"},
      {"tof_scale", "the ToF reading is off in proportion to the range"},
      {"capacity_scale", "the battery holds a different charge than the calibration batteries"},
  };
  if (cause.rfind("covariate:", 0) == 0) return "the readings drift with the column " + cause.substr(10);
  const auto it = m.find(cause);
  return it == m.end() ? cause : it->second;
}

/// Parameters named "gains[3]" become arrays (null where a sensor was not seen or is the reference).
void put_parameters(const std::vector<dg::NamedValue>& values, nlohmann::json& value_out, nlohmann::json& error_out) {
  value_out = nlohmann::json::object();
  error_out = nlohmann::json::object();
  auto number = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  for (const auto& v : values) {
    const auto open = v.name.find('[');
    if (open == std::string::npos) {
      value_out[v.name] = number(v.value);
      error_out[v.name] = number(v.std_error);
      continue;
    }
    const std::string key = v.name.substr(0, open);
    const std::size_t index = std::stoul(v.name.substr(open + 1));
    for (nlohmann::json* j : {&value_out, &error_out}) {
      if (!j->contains(key)) (*j)[key] = nlohmann::json::array();
      while ((*j)[key].size() <= index) (*j)[key].push_back(nullptr);
    }
    value_out[key][index] = number(v.value);
    error_out[key][index] = number(v.std_error);
  }
}

/// {name: why} for the standard errors written as null (the data do not determine them); empty
/// when there is none.
nlohmann::json undefined_errors(const std::vector<dg::NamedValue>& values) {
  nlohmann::json why = nlohmann::json::object();
  for (const auto& v : values)
    if (!std::isfinite(v.std_error)) why[v.name] = v.std_error_why.empty() ? std::string("undefined") : v.std_error_why;
  return why;
}

nlohmann::json to_json(const dg::Report& r, const std::vector<std::string>& paths) {
  nlohmann::json j;
  j["kind"] = std::string(logs::to_string(r.kind));
  j["rows"] = r.rows;
  j["residuals"] = r.residuals;
  j["logs"] = paths;
  j["verdict"] = r.verdict;
  j["too_few_rows"] = r.too_few_rows;
  j["minimum_rows"] = r.minimum_rows;
  if (r.too_few_rows) {
    // Only the plug-in's error on every row: nothing was fitted, so every other figure is null
    // with the reason beside it.
    j["message"] = r.message;
    const std::string why = "not computed: " + r.message;
    j["recalibrated"] = nlohmann::json::object();
    j["recalibrated_uncertainty"] = nlohmann::json::object();
    j["heldout_mse_plugin"] = r.heldout_mse_plugin;
    for (const char* key : {"heldout_mse_recalibrated", "heldout_mse_final", "noise_sd"}) {
      j[key] = nullptr;
      j[std::string(key) + "_why"] = why;
    }
    j["mse_units"] = units(r.kind);
    j["findings"] = nlohmann::json::array();
    j["residual_structure"] = nlohmann::json::array();
    j["residual_structure_before"] = nlohmann::json::array();
    j["effects_considered"] = r.effects_considered;
    j["outliers"] = {{"count", r.outliers.size()}, {"rows", r.outliers}};
    j["censored"] = r.censored;
    j["warnings"] = r.warnings;
    j["search"] = nlohmann::json::array();
    j["notes"] = r.notes;
    return j;
  }
  nlohmann::json rec, rec_se;
  put_parameters(r.recalibrated, rec, rec_se);
  j["recalibrated"] = rec;
  j["recalibrated_uncertainty"] = rec_se;
  if (const auto why = undefined_errors(r.recalibrated); !why.empty()) j["recalibrated_uncertainty_why"] = why;
  j["heldout_mse_plugin"] = r.heldout_mse_plugin;
  j["heldout_mse_recalibrated"] = r.heldout_mse_base;
  j["heldout_mse_final"] = r.heldout_mse_final;
  if (!r.channel_noise_sd.empty()) {
    j["heldout_weighted_recalibrated"] = r.heldout_weighted_base;
    j["heldout_weighted_final"] = r.heldout_weighted_final;
  }
  j["noise_sd"] = r.noise_sd;
  j["mse_units"] = units(r.kind);
  if (!r.channel_noise_sd.empty()) {
    nlohmann::json c = nlohmann::json::object();
    for (const auto& v : r.channel_noise_sd) c[v.name] = v.value;
    j["channel_noise_sd"] = c;
  }
  j["findings"] = nlohmann::json::array();
  for (const auto& f : r.findings) {
    nlohmann::json fj, v, e;
    fj["cause"] = f.cause;
    put_parameters(f.parameters, v, e);
    fj["parameters"] = v;
    fj["uncertainty"] = e;
    if (const auto why = undefined_errors(f.parameters); !why.empty()) fj["uncertainty_why"] = why;
    fj["heldout_mse_before"] = f.heldout_mse_before;
    fj["heldout_mse_after"] = f.heldout_mse_after;
    if (!r.channel_noise_sd.empty()) {
      fj["heldout_weighted_before"] = f.heldout_weighted_before;
      fj["heldout_weighted_after"] = f.heldout_weighted_after;
    }
    fj["delta_bic"] = f.delta_bic;
    fj["meaning"] = meaning(f.cause);
    fj["alternatives"] = f.alternatives;
    j["findings"].push_back(fj);
  }
  auto scores = [](const std::vector<dg::CovariateScore>& s) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& c : s) {
      a.push_back({{"covariate", c.covariate}, {"score", c.score}, {"significant", c.significant}});
      if (!c.channel.empty()) a.back()["channel"] = c.channel;
    }
    return a;
  };
  j["residual_structure"] = scores(r.structure_after);
  j["residual_structure_before"] = scores(r.structure_before);
  j["effects_considered"] = r.effects_considered;
  j["outliers"] = {{"count", r.outliers.size()}, {"rows", r.outliers}};
  j["censored"] = r.censored;
  j["warnings"] = r.warnings;
  nlohmann::json trials = nlohmann::json::array();
  for (const auto& t : r.trials)
    trials.push_back({{"step", t.step}, {"cause", t.cause}, {"delta_bic", t.delta_bic},
                      {"heldout_mse", t.heldout_mse > 0 ? nlohmann::json(t.heldout_mse) : nlohmann::json(nullptr)},
                      {"kept", t.kept}, {"screened_out", t.screened_out}});
  j["search"] = trials;
  j["notes"] = r.notes;
  // The extended model (base in the final joint fit, the findings as effects, the final noise):
  // the report doubles as a coefficient file for `simulate KIND --like`, `codegen` and ARGoS.
  nlohmann::json model = dg::extended_model_json(r);
  if (!model.empty()) {
    nlohmann::json fb, fb_se;
    put_parameters(r.final_base.empty() ? r.recalibrated : r.final_base, fb, fb_se);
    j["final_base"] = fb;
    for (const char* key : {"parameters", "effects", "noise", "effects_not_in_model"})
      if (model.contains(key)) j[key] = model[key];
  }
  return j;
}

std::string format_parameters(const std::vector<dg::NamedValue>& values) {
  std::string out;
  char buf[160];
  for (const auto& v : values) {
    if (std::isfinite(v.std_error) && v.std_error > 0)
      std::snprintf(buf, sizeof buf, "%s%s = %.4g +- %.2g", out.empty() ? "" : ", ", v.name.c_str(), v.value, v.std_error);
    else
      std::snprintf(buf, sizeof buf, "%s%s = %.4g", out.empty() ? "" : ", ", v.name.c_str(), v.value);
    out += buf;
  }
  return out;
}

void print_report(const dg::Report& r) {
  const std::string u = units(r.kind);
  std::printf("Diagnosis of %zu %s rows (%zu residuals)\n", r.rows, std::string(logs::to_string(r.kind)).c_str(), r.residuals);
  std::printf("The plug-in's model with the coefficients given, before recalibration: MSE %.4g %s.\n", r.heldout_mse_plugin,
              u.c_str());
  if (r.too_few_rows) {
    const std::string m = r.message.empty() ? r.message : std::string(1, static_cast<char>(std::toupper(r.message[0]))) + r.message.substr(1);
    std::printf("%s.\nNo effect was judged: no recalibration, no search, no finding.\n", m.c_str());
    if (!r.outliers.empty()) std::printf("Wild readings left out before the diagnosis: %zu\n", r.outliers.size());
    std::printf("Verdict: none (too few rows to judge)\n");
    return;
  }
  if (!r.channel_noise_sd.empty()) {
    std::printf("Channels fitted together, each weighted by its noise:");
    for (const auto& c : r.channel_noise_sd) std::printf(" %s (sd %.3g)", c.name.c_str(), c.value);
    std::printf("; held-out MSEs below are the %s's.\n", r.channel_noise_sd.front().name.c_str());
  }
  if (!r.recalibrated.empty())
    std::printf("Recalibrated base model (%s): held-out MSE %.4g %s. This is what recalibration alone fixes, not an effect.\n",
                format_parameters(r.recalibrated).c_str(), r.heldout_mse_base, u.c_str());
  else
    std::printf("The base model has no free parameter: held-out MSE %.4g %s.\n", r.heldout_mse_base, u.c_str());
  if (!r.structure_before.empty() && r.structure_before.front().significant)
    std::printf("Its residuals depend most on %s (%.0f %% of their variance).\n", r.structure_before.front().covariate.c_str(),
                100 * r.structure_before.front().score);
  for (const auto& f : r.findings) {
    std::printf("Finding: %s (%s); %s explains it; held-out MSE %.4g -> %.4g %s", f.cause.c_str(), meaning(f.cause).c_str(),
                format_parameters(f.parameters).c_str(), f.heldout_mse_before, f.heldout_mse_after, u.c_str());
    if (!r.channel_noise_sd.empty())
      std::printf(", all channels weighted %.4g -> %.4g", f.heldout_weighted_before, f.heldout_weighted_after);
    std::printf(" (BIC %+.1f).\n", f.delta_bic);
  }
  for (const auto& f : r.findings)
    if (!f.alternatives.empty()) {
      std::string alts;
      for (const auto& a : f.alternatives) alts += (alts.empty() ? "" : ", ") + a;
      std::printf("Note: these logs cannot tell %s from %s (they fit almost as well).\n", f.cause.c_str(), alts.c_str());
    }
  for (const auto& n : r.notes) std::printf("Note: %s.\n", n.c_str());
  if (r.censored > 0) std::printf("Readings on a sensor's rails: %zu (modelled through the clamp).\n", r.censored);
  if (!r.outliers.empty()) {
    std::printf("Wild readings left out before the diagnosis: %zu\n", r.outliers.size());
    for (std::size_t k = 0; k < r.outliers.size() && k < 5; ++k) std::printf("  %s\n", r.outliers[k].c_str());
  }
  if (r.findings.empty()) std::printf("No effect of the catalogue passes both the BIC and the held-out test.\n");
  std::printf("Residual structure left:");
  for (std::size_t k = 0; k < r.structure_after.size() && k < 4; ++k)
    std::printf(" %s %.3f%s", r.structure_after[k].covariate.c_str(), r.structure_after[k].score,
                r.structure_after[k].significant ? " (significant)" : "");
  std::printf("\nVerdict: %s", r.verdict.c_str());
  if (r.verdict == "unexplained")
    std::printf(" (the residuals%s still depend on %s, which no effect of the catalogue explains)",
                r.structure_after.front().channel.empty() ? "" : (" of " + r.structure_after.front().channel).c_str(),
                r.structure_after.front().covariate.c_str());
  std::printf("\n");
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
  for (const auto& l : logs) log_names.push_back(l.path);
  dg::Options options;
  if (!models::battery::parse_model(o.battery_model, options.battery_model))
    throw UsageError("--battery-model: " + unknown_name("discharge model", o.battery_model, {"simple", "linear", "cubic", "approximated"}));
  if (o.coefficients.empty() || o.coefficients == "plugin") options.battery_tables = models::battery::plugin_tables();
  else if (o.coefficients == "fitted") {
#ifdef EPUCK2_FITTED_HAS_BATTERY
    options.battery_tables = fitted::battery_tables();
#else
    throw UsageError("this build has no compiled-in fitted battery tables; give --coefficients FILE");
#endif
  } else
    options.battery_tables = calibrate::battery_tables_from_json(read_json(coefficient_file(o.coefficients)), o.coefficients);
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
  const dg::Report r = dg::diagnose(std::move(logs), options);  // the logs are released once read
  if (options.progress && tty) std::fprintf(stderr, "\r\033[K");
  if (!r.supported) throw UsageError(r.message);
  for (const auto& w : r.warnings) std::fprintf(stderr, "diagnose: warning: %s\n", w.c_str());
  // All or nothing: the JSON report and the figure are renamed into place together, then printed.
  const std::string text = o.json || !output.empty() ? json_text(to_json(r, o.logs)) : std::string();
  const std::string figure = figure_path(o.plot, r.kind);
  logs::OutputStage stage;
  if (!output.empty()) stage.write(output, text);
  if (!figure.empty()) plot::diagnosis_figure(stage, figure, r, log_names);
  stage.commit();
  if (!output.empty()) std::cerr << "diagnose: wrote " << output << '\n';
  if (!figure.empty()) std::cerr << "diagnose: drew " << figure << '\n';
  if (o.json) std::cout << text;
  else print_report(r);
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
  sub->add_option("-o,--output", o->output, "Write the JSON report to FILE, atomically")->type_name("FILE");
  sub->add_option("--json-file", o->json_file)->group("");  // what main.cpp makes of the old --json FILE.json
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
      ->type_name("FILE");
  sub->add_option("--battery-model", o->battery_model, "battery: the discharge model simulated")
      ->capture_default_str()
      ->check(one_of({"simple", "linear", "cubic", "approximated"}, "discharge model"));
  sub->add_option("--coefficients", o->coefficients,
                  "battery: coefficient tables: plugin (the plug-in's published ones, default), fitted (the CLI's compiled-in data/fitted tables) or a battery JSON FILE");
  sub->add_option("logs", o->logs, "Log files of one kind (CSV, docs/logs.md)")->required()->check(CLI::ExistingFile);
  sub->add_flag("--progress", o->progress,
                "Show progress on standard error (stage, effect being fitted); on by default when standard error is a terminal");
  sub->footer(all_log_formats_footer());
  add_skip_bad_rows(sub, o->skip_bad_rows);
  sub->callback([o, &action] { action = [o] { return run_diagnose(*o); }; });
}

}  // namespace epuck2::app
