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
  std::size_t battery_model_given = 0;  ///< --battery-model on the command line (else a file's may set it)
  std::string coefficients;
  std::string effects;  ///< --effects: the search's effects, comma-separated (empty: all)
  std::vector<std::string> logs;
  bool skip_bad_rows = false;
  bool progress = false;
};

/// --effects' list: the names between commas. One value, split here (CLI11's delimiter dropped
/// empty names and let `--effects ,` take the next argument, `-o`, as an effect): an empty name
/// is a usage error.
std::vector<std::string> effect_list(const std::string& list) {
  std::vector<std::string> names;
  if (list.empty()) return names;
  std::size_t from = 0;
  for (;;) {
    const std::size_t comma = list.find(',', from);
    names.push_back(list.substr(from, comma == std::string::npos ? std::string::npos : comma - from));
    if (names.back().empty())
      throw UsageError("--effects '" + list + "': an empty effect name; give the names between commas, e.g. black_offset,white_level");
    if (comma == std::string::npos) return names;
    from = comma + 1;
  }
}

std::string units_of(logs::Kind k) {
  switch (k) {
    case logs::Kind::camera: return "px^2";
    case logs::Kind::drive: return "mm^2 (ToF)";
    case logs::Kind::battery: return "charge^2";
    default: return "counts^2";
  }
}

/// The residuals' unit (the MSE's is its square).
std::string residual_unit(logs::Kind k) {
  switch (k) {
    case logs::Kind::camera: return "px";
    case logs::Kind::drive: return "mm";
    case logs::Kind::battery: return "charge";
    default: return "counts";
  }
}

/// A catalogue parameter's unit, from its name (docs/diagnose.md's catalogue).
std::string parameter_unit(logs::Kind kind, const std::string& name) {
  const std::string base = name.substr(0, name.find('['));
  if (base == "slope") return residual_unit(kind) + " per unit of the column";
  // A catalogue parameter: its unit in the registry (lib/models effects.hpp).
  if (const auto* c = models::effects::catalogue(std::string(logs::to_string(kind))))
    for (const auto& e : *c)
      if (const auto* p = e.param(base)) return std::string(p->unit) == "counts" ? residual_unit(kind) : p->unit;
  auto ends = [&](const std::string& suffix) {
    return base.size() >= suffix.size() && base.compare(base.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (ends("_cm_s2")) return "cm/s^2";
  if (ends("_cm_s")) return "cm/s";
  if (ends("_mm")) return "mm";
  if (ends("_px")) return "px";
  if (ends("_deg")) return "deg";
  if (ends("_m")) return "m";
  if (ends("_s")) return "s";
  if (kind == logs::Kind::proximity && base == "a") return "1/m^2";
  if (kind == logs::Kind::proximity && base == "b") return "1/m";
  if (base == "offset" || base == "amplitude" || base == "level") return residual_unit(kind);
  if (base == "slope") return residual_unit(kind) + " per unit of the column";
  return "1";
}

/// How the diagnosis fits, in words (the loss and the censoring).
const char* kDiagnosisLoss =
    "least squares on the expected reading E[clamp(model + noise)] (readings on a rail enter through the clamp's "
    "expected value), each channel's residuals weighted by the reading's noise sd over its own";

/// What a cause means, in plain words: the registry's meaning (lib/models effects.hpp), or a
/// covariate's column, or a renamed finding's.
std::string meaning(logs::Kind kind, const std::string& cause) {
  if (cause.rfind(models::effects::kCovariatePrefix, 0) == 0)
    return "the readings drift with the column " + cause.substr(std::string(models::effects::kCovariatePrefix).size());
  if (const auto* c = models::effects::catalogue(std::string(logs::to_string(kind))))
    if (const auto* e = models::effects::find(*c, cause)) return e->meaning;
  return dg::finding_meaning(cause);
}

/// Parameters named "gains[3]" become arrays (null where a sensor was not seen or is the reference).
void put_parameters(const std::vector<dg::NamedValue>& values, nlohmann::json& value_out, nlohmann::json& error_out,
                    nlohmann::json* corrected_out = nullptr, nlohmann::json* jackknife_out = nullptr) {
  value_out = nlohmann::json::object();
  error_out = nlohmann::json::object();
  nlohmann::json corrected = nlohmann::json::object(), jackknife = nlohmann::json::object();
  auto number = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  for (const auto& v : values) {
    const auto open = v.name.find('[');
    if (open == std::string::npos) {
      value_out[v.name] = number(v.value);
      error_out[v.name] = number(v.std_error);
      corrected[v.name] = number(v.std_error_corrected);
      jackknife[v.name] = number(v.std_error_jackknife);
      continue;
    }
    const std::string key = v.name.substr(0, open);
    const std::size_t index = std::stoul(v.name.substr(open + 1));
    for (nlohmann::json* j : {&value_out, &error_out, &corrected, &jackknife}) {
      if (!j->contains(key)) (*j)[key] = nlohmann::json::array();
      while ((*j)[key].size() <= index) (*j)[key].push_back(nullptr);
    }
    value_out[key][index] = number(v.value);
    error_out[key][index] = number(v.std_error);
    corrected[key][index] = number(v.std_error_corrected);
    jackknife[key][index] = number(v.std_error_jackknife);
  }
  if (corrected_out != nullptr) *corrected_out = corrected;
  if (jackknife_out != nullptr) *jackknife_out = jackknife;
}

/// "name = value ± error unit": the largest of the standard errors the report has (the
/// covariance's, the autocorrelation-corrected one for a time series, the jackknife over the
/// held-out folds), the value rounded to it, and which it is; the others beside it.
std::string format_value(logs::Kind kind, const dg::NamedValue& v) {
  std::string why = v.std_error_why;
  if (why.empty() && v.std_error == 0) why = "held";
  const std::string unit = parameter_unit(kind, v.name) == "1" ? "" : fit::pretty_unit(parameter_unit(kind, v.name));
  if (!(std::isfinite(v.std_error) && v.std_error > 0)) return v.name + " = " + fit::format_uncertain(v.value, v.std_error, unit, why);
  struct Error {
    double se;
    const char* what;
  };
  std::vector<Error> errors{{v.std_error, "covariance"}};
  if (std::isfinite(v.std_error_corrected) && v.std_error_corrected > 0)
    errors.push_back({v.std_error_corrected, "corrected for autocorrelation"});
  if (std::isfinite(v.std_error_jackknife) && v.std_error_jackknife > 0)
    errors.push_back({v.std_error_jackknife, "jackknife over the held-out folds"});
  const auto top = std::max_element(errors.begin(), errors.end(), [](const Error& a, const Error& b) { return a.se < b.se; });
  std::string text = v.name + " = " + fit::format_uncertain(v.value, top->se, unit) + " (" + top->what;
  for (const Error& e : errors)
    if (&e != &*top) text += std::string("; ") + e.what + " ± " + fit::format_error(e.se);
  return text + ")";
}

/// {name: "value ± error unit"} as the report prints them.
nlohmann::json rounded(logs::Kind kind, const std::vector<dg::NamedValue>& values) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& v : values) j[v.name] = format_value(kind, v).substr(v.name.size() + 3);
  return j;
}

/// {name: why} for the standard errors written as null (the data do not determine them); empty
/// when there is none.
nlohmann::json undefined_errors(const std::vector<dg::NamedValue>& values) {
  nlohmann::json why = nlohmann::json::object();
  for (const auto& v : values)
    if (!std::isfinite(v.std_error)) why[v.name] = v.std_error_why.empty() ? std::string("undefined") : v.std_error_why;
  return why;
}

nlohmann::json to_json(const dg::Report& r, const std::vector<std::string>& paths, const dg::ModelInputs& inputs) {
  nlohmann::json j;
  j["kind"] = std::string(logs::to_string(r.kind));
  j["rows"] = r.rows;
  j["residuals"] = r.residuals;
  j["logs"] = paths;
  j["verdict"] = r.verdict_name();
  if (const dg::Finding* d = r.dominant()) j["most_of_the_gain"] = d->cause;
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
    j["mse_units"] = units_of(r.kind);
    j["findings"] = nlohmann::json::array();
    j["possible_findings"] = nlohmann::json::array();
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
  nlohmann::json rec, rec_se, rec_corrected;
  put_parameters(r.recalibrated, rec, rec_se, &rec_corrected);
  j["recalibrated"] = rec;
  j["recalibrated_uncertainty"] = rec_se;
  j["recalibrated_rounded"] = rounded(r.kind, r.recalibrated);
  {
    nlohmann::json unused_values, unused_errors, jackknife;
    put_parameters(r.recalibrated, unused_values, unused_errors, nullptr, &jackknife);
    j["recalibrated_uncertainty_jackknife"] = jackknife;
  }
  j["jackknife_folds"] = r.jackknife_folds;
  if (r.time_series) j["recalibrated_uncertainty_corrected"] = rec_corrected;
  const std::string rss_unit = residual_unit(r.kind) + "^2";
  j["loss"] = kDiagnosisLoss;
  j["censored_per_rail"] = {{"at_or_below", r.censored_below}, {"at_or_above", r.censored_above}};
  j["statistics_conventions"] = calibrate::statistics_conventions_json();
  j["fit"] = {{"recalibrated", calibrate::statistics_json(r.base_fit, rss_unit)},
              {"final", calibrate::statistics_json(r.final_fit, rss_unit)}};
  j["correlations"] = calibrate::correlations_json(r.correlations);
  if (r.time_series) {
    j["autocorrelation"] = calibrate::autocorrelation_json(r.autocorrelation);
    if (r.autocorrelation.computed) j["autocorrelation"]["channel"] = r.autocorrelation_channel;
  }
  nlohmann::json units = {{"mse", units_of(r.kind)}, {"rss", rss_unit}, {"noise_sd", residual_unit(r.kind)}};
  for (const auto& v : r.recalibrated) units[v.name.substr(0, v.name.find('['))] = parameter_unit(r.kind, v.name);
  for (const auto& f : r.findings)
    for (const auto& v : f.parameters) units[v.name.substr(0, v.name.find('['))] = parameter_unit(r.kind, v.name);
  j["units"] = units;
  if (const auto why = undefined_errors(r.recalibrated); !why.empty()) j["recalibrated_uncertainty_why"] = why;
  j["heldout_mse_plugin"] = r.heldout_mse_plugin;
  j["heldout_mse_recalibrated"] = r.heldout_mse_base;
  j["heldout_mse_final"] = r.heldout_mse_final;
  if (!r.channel_noise_sd.empty()) {
    j["heldout_weighted_recalibrated"] = r.heldout_weighted_base;
    j["heldout_weighted_final"] = r.heldout_weighted_final;
  }
  j["noise_sd"] = r.noise_sd;
  j["mse_units"] = units_of(r.kind);
  if (!r.channel_noise_sd.empty()) {
    nlohmann::json c = nlohmann::json::object();
    for (const auto& v : r.channel_noise_sd) c[v.name] = v.value;
    j["channel_noise_sd"] = c;
  }
  j["findings"] = nlohmann::json::array();
  for (const auto& f : r.findings) {
    nlohmann::json fj, v, e, corrected, jackknife;
    fj["cause"] = f.cause;
    if (f.effect != f.cause) fj["effect"] = f.effect;  // the catalogue formula it carries
    if (!f.renamed_from.empty()) fj["renamed_from"] = f.renamed_from;
    put_parameters(f.parameters, v, e, &corrected, &jackknife);
    fj["uncertainty_jackknife"] = jackknife;
    fj["parameters"] = v;
    fj["uncertainty"] = e;
    if (r.time_series) fj["uncertainty_corrected"] = corrected;
    fj["rounded"] = rounded(r.kind, f.parameters);
    fj["fit"] = calibrate::statistics_json(f.fit, rss_unit);
    if (const auto why = undefined_errors(f.parameters); !why.empty()) fj["uncertainty_why"] = why;
    fj["heldout_mse_before"] = f.heldout_mse_before;
    fj["heldout_mse_after"] = f.heldout_mse_after;
    if (!r.channel_noise_sd.empty()) {
      fj["heldout_weighted_before"] = f.heldout_weighted_before;
      fj["heldout_weighted_after"] = f.heldout_weighted_after;
    }
    fj["delta_bic"] = f.delta_bic;
    fj["removal_delta_bic"] = f.removal_delta_bic;
    fj["meaning"] = meaning(r.kind, f.cause);
    fj["alternatives"] = f.alternatives;
    if (!f.accepted_with.empty()) fj["accepted_with"] = f.accepted_with;  // the pair search's
    j["findings"].push_back(fj);
  }
  // Kept by the search, not determined by the logs: not in the extended model (docs/diagnose.md).
  j["possible_findings"] = nlohmann::json::array();
  for (const auto& f : r.possible) {
    nlohmann::json fj, v, e;
    fj["cause"] = f.cause;
    fj["status"] = f.outside_physical_range ? "not written" : "possible, not determined";
    fj["why"] = f.undetermined;
    put_parameters(f.parameters, v, e, nullptr, nullptr);
    fj["parameters"] = v;
    fj["uncertainty"] = e;
    fj["delta_bic"] = f.delta_bic;
    fj["meaning"] = meaning(r.kind, f.cause);
    j["possible_findings"].push_back(fj);
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
  for (std::size_t k = 0; k < r.trials.size(); ++k)
    if (!r.trials[k].with.empty()) trials[k]["with"] = r.trials[k].with;  // a pair fitted jointly
  j["search"] = trials;
  j["notes"] = r.notes;
  // The extended model (base in the final joint fit, the findings as effects, the final noise;
  // battery: the discharge model and tables the diagnosis ran): the report doubles as a
  // coefficient file for `simulate KIND --like`, `codegen` and ARGoS.
  const nlohmann::json model = dg::extended_model_json(r, inputs);
  nlohmann::json fb, fb_se;
  put_parameters(r.final_base.empty() ? r.recalibrated : r.final_base, fb, fb_se);
  j["final_base"] = fb;
  for (const auto& [key, value] : model.items())
    if (key != "kind") j[key] = value;
  return j;
}

std::string format_parameters(logs::Kind kind, const std::vector<dg::NamedValue>& values) {
  std::string out;
  for (const auto& v : values) out += (out.empty() ? "" : ", ") + format_value(kind, v);
  return out;
}

/// "n .., k .., RSS .., MSE .., reduced chi^2 .., R^2 .., AIC .., BIC .." of a fit to all rows.
std::string format_statistics(const fit::FitStatistics& s, const std::string& unit) {
  char buf[600];
  const std::string u2 = fit::pretty_unit(unit + "^2");
  std::snprintf(buf, sizeof buf, "n %zu, k %d, RSS %.4g %s, MSE %.4g %s, reduced χ² = RSS/(n-k) %.4g %s, R² %.5f, %s",
                s.n, s.k, s.rss, u2.c_str(), s.mse, u2.c_str(), s.reduced_chi2, u2.c_str(), s.r2,
                fit::format_information_criteria(s, 1).c_str());
  return buf;
}

/// The base model as it is named in the report: the plug-in's, or FILE's (--coefficients).
std::string base_model_name(const std::string& coefficients) {
  if (coefficients.empty() || coefficients == "plugin") return "The plug-in's model with the coefficients given";
  if (coefficients == "fitted") return "The plug-in's model with the CLI's compiled-in fitted battery tables";
  return logs::escape_control(coefficients) + "'s model with its coefficients";
}

void print_report(const dg::Report& r, const std::string& base_name) {
  const std::string u = fit::pretty_unit(units_of(r.kind));
  std::printf("Diagnosis of %zu %s rows (%zu residuals)\n", r.rows, std::string(logs::to_string(r.kind)).c_str(), r.residuals);
  std::printf("%s, before recalibration: MSE %.4g %s.\n", base_name.c_str(), r.heldout_mse_plugin, u.c_str());
  if (r.too_few_rows) {
    const std::string m = r.message.empty() ? r.message : std::string(1, static_cast<char>(std::toupper(r.message[0]))) + r.message.substr(1);
    std::printf("%s.\nNo effect was judged: no recalibration, no search, no finding.\n", m.c_str());
    if (!r.outliers.empty()) std::printf("Wild readings left out before the diagnosis: %zu\n", r.outliers.size());
    std::printf("Verdict: %s\n", r.verdict_name().c_str());
    return;
  }
  if (!r.channel_noise_sd.empty()) {
    std::printf("Channels fitted together, each weighted by its noise:");
    for (const auto& c : r.channel_noise_sd) std::printf(" %s (sd %.3g)", c.name.c_str(), c.value);
    std::printf("; held-out MSEs below are the %s's.\n", r.channel_noise_sd.front().name.c_str());
  }
  const std::string ru = residual_unit(r.kind);
  std::printf("Loss: %s. Readings on a rail: %zu at or below the low one, %zu at or above the high one.\n", kDiagnosisLoss,
              r.censored_below, r.censored_above);
  if (!r.recalibrated.empty())
    std::printf("Recalibrated base model (%s): held-out MSE %.4g %s. This is what recalibration alone fixes, not an effect.\n",
                format_parameters(r.kind, r.recalibrated).c_str(), r.heldout_mse_base, u.c_str());
  else
    std::printf("The base model has no free parameter: held-out MSE %.4g %s.\n", r.heldout_mse_base, u.c_str());
  std::printf("  fit to all rows: %s\n", format_statistics(r.base_fit, ru).c_str());
  if (!r.structure_before.empty() && r.structure_before.front().significant)
    std::printf("Its residuals depend most on %s (%.0f %% of their variance).\n", r.structure_before.front().covariate.c_str(),
                100 * r.structure_before.front().score);
  for (const auto& f : r.findings) {
    std::printf("Finding: %s (%s); %s explains it; held-out MSE %.4g -> %.4g %s", f.cause.c_str(), meaning(r.kind, f.cause).c_str(),
                format_parameters(r.kind, f.parameters).c_str(), f.heldout_mse_before, f.heldout_mse_after, u.c_str());
    if (!r.channel_noise_sd.empty())
      std::printf(", all channels weighted %.4g -> %.4g", f.heldout_weighted_before, f.heldout_weighted_after);
    if (f.accepted_with.empty()) std::printf(" (BIC %+.1f).\n", f.delta_bic);
    else std::printf(" (BIC %+.1f, the pair's: accepted together with %s).\n", f.delta_bic, f.accepted_with.c_str());
    std::printf("  fit to all rows with it: %s\n", format_statistics(f.fit, ru).c_str());
  }
  if (r.findings.size() > 1) {
    std::printf("Most of the gain: %s (taken out of the final model, the BIC rises by", r.dominant()->cause.c_str());
    for (const auto& f : r.findings) std::printf(" %s %+.1f", f.cause.c_str(), f.removal_delta_bic);
    std::printf(").\n");
  }
  for (const auto& f : r.possible)
    std::printf("%s: %s (%s): %s; left out of the extended model.\n", f.outside_physical_range ? "Not written" : "Possible, not determined", f.cause.c_str(),
                meaning(r.kind, f.cause).c_str(), f.undetermined.c_str());
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
  std::printf("Final model: %s (AIC n ln(RSS/n) + 2k, BIC n ln(RSS/n) + k ln n, as lmfit", format_statistics(r.final_fit, ru).c_str());
  std::printf("%s)\n", r.channel_noise_sd.empty() ? "" : "; residuals weighted by their channel's noise, in the first channel's units");
  std::printf("  correlations (|r| > 0.1):");
  if (r.correlations.empty()) std::printf(" none");
  for (std::size_t k = 0; k < r.correlations.size(); ++k)
    std::printf("%s %s-%s %+.3f", k ? "," : "", r.correlations[k].a.c_str(), r.correlations[k].b.c_str(), r.correlations[k].r);
  std::printf("\n");
  if (r.time_series) {
    const auto& a = r.autocorrelation;
    if (a.computed)
      std::printf("  a log's rows are a time series: the residuals' lag-1 autocorrelation %.5f (%s) gives AR(1) "
                  "n_eff = n (1-rho)/(1+rho) = %.4g of %zu, factor %.3g\n",
                  a.rho, r.autocorrelation_channel.c_str(), a.n_eff, a.n, a.factor);
    else
      std::printf("  a log's rows are a time series, but the residuals' lag-1 autocorrelation was not estimated (%s)\n",
                  a.why_not.c_str());
    if (a.cluster_robust)
      std::printf("  [corrected for autocorrelation] errors: cluster-robust with each of the %zu logs a cluster (sandwich, "
                  "G/(G-1)), never below the covariance's: a misfit that lasts a whole log counts once per log\n",
                  a.series);
    else
      std::printf("  [corrected for autocorrelation] errors: the covariance's times the AR(1) factor (not cluster-robust: %s)\n",
                  a.cluster_why_not.c_str());
  }
  for (const auto& w : r.warnings) std::printf("Warning: %s\n", w.c_str());
  std::printf("Residual structure left:");
  for (std::size_t k = 0; k < r.structure_after.size() && k < 4; ++k)
    std::printf(" %s %.3f%s", r.structure_after[k].covariate.c_str(), r.structure_after[k].score,
                r.structure_after[k].significant ? " (significant)" : "");
  std::printf("\nVerdict: %s", r.verdict_name().c_str());
  if (r.verdict == diagnose::Verdict::unexplained)
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
  std::vector<std::string> log_robots;  // the figure's marker per robot
  for (const auto& l : logs) {
    log_names.push_back(l.path);
    log_robots.push_back(l.robot);
  }
  dg::Options options;
  if (!models::battery::parse_model(o.battery_model, options.battery_model))
    throw UsageError("--battery-model: " + unknown_name("discharge model", o.battery_model, {"simple", "linear", "cubic", "approximated"}));
  const logs::Kind logs_kind = logs.front().kind;
  if (logs_kind != logs::Kind::battery && !o.coefficients.empty() && o.coefficients != "plugin") {
    // The other kinds: the base model from a coefficient file (a calibration's or a diagnosis's).
    if (o.coefficients == "fitted")
      throw UsageError("--coefficients fitted names the battery tables compiled in; for " +
                       std::string(logs::to_string(logs_kind)) + " logs give the coefficient FILE (data/fitted/" +
                       std::string(logs::to_string(logs_kind)) + ".json in this repository)");
    const std::string& file = coefficient_file(o.coefficients);
    const nlohmann::json j = read_json(file);
    try {
      switch (logs_kind) {
        case logs::Kind::proximity: options.base_model = coefficients::proximity_model_from_json(j, file); break;
        case logs::Kind::light: options.base_model = coefficients::light_model_from_json(j, file); break;
        case logs::Kind::ground: options.base_model = coefficients::ground_model_from_json(j, file); break;
        case logs::Kind::camera: options.base_model = coefficients::camera_model_from_json(j, file); break;
        case logs::Kind::drive: options.base_model = coefficients::drive_model_from_json(j, file); break;
        default: break;
      }
    } catch (const logs::InputError&) {
      throw;
    } catch (const std::runtime_error& e) {
      throw UsageError(std::string("--coefficients: ") + e.what());
    }
  } else if (o.coefficients.empty() || o.coefficients == "plugin") options.battery_tables = models::battery::plugin_tables();
  else if (o.coefficients == "fitted") {
#ifdef EPUCK2_FITTED_HAS_BATTERY
    options.battery_tables = fitted::battery_tables();
#else
    throw UsageError("this build has no compiled-in fitted battery tables; give --coefficients FILE");
#endif
  } else {
    // A battery file: its tables; a diagnosis's (an extended model) also its discharge model,
    // unless --battery-model names one, and its capacity scale, from which effects are changes.
    const std::string& file = coefficient_file(o.coefficients);
    const nlohmann::json j = read_json(file);
    try {
      const models::sensors::BatteryModel m = coefficients::battery_model_from_json(j, file);
      options.battery_tables = m.tables;
      options.battery_capacity_k = m.capacity.k;
      if (j.contains("battery_model") && o.battery_model_given == 0) options.battery_model = m.model;
    } catch (const logs::InputError&) {
      throw;
    } catch (const std::runtime_error& e) {
      throw UsageError(std::string("--coefficients: ") + e.what());
    }
  }
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
  for (const auto& w : r.warnings) std::fprintf(stderr, "diagnose: warning: %s\n", w.c_str());
  // All or nothing: the JSON report and the figure are renamed into place together, then printed.
  const std::string text = o.json || !output.empty() ? json_text(to_json(r, o.logs, inputs)) : std::string();
  const std::string figure = figure_path(o.plot, r.kind);
  logs::OutputStage stage;
  if (!output.empty()) stage.write(output, text);
  if (!figure.empty()) plot::diagnosis_figure(stage, figure, r, log_names, log_robots);
  stage.commit();
  if (!output.empty()) std::cerr << "diagnose: wrote " << output << '\n';
  if (!figure.empty()) std::cerr << "diagnose: drew " << figure << '\n';
  print_figure_warnings("diagnose");
  if (o.json) std::cout << text;
  else print_report(r, base_model_name(o.coefficients));
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
  sub->add_option("-o,--output", o->output, "Write the JSON report to FILE, atomically")->type_name("FILE")->check(output_file());
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
  sub->add_option("--effects", o->effects,
                  "Search only these effects of the catalogue, comma-separated (e.g. black_offset,white_level); default: all")
      ->check(CLI::Validator(
          [](std::string& input) -> std::string {
            if (input.empty()) return "an empty list; give effect names between commas, e.g. black_offset,white_level";
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
