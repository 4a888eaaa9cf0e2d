// A diagnosis's report as its two outputs (docs/diagnose.md): the JSON (which doubles as a
// coefficient file: the extended model's sections) and the human report. The units come from the
// kind's facts and the effect registry (lib/models), the meanings from the registry.
#include "epuck2/diagnose/report_output.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "epuck2/calibrate/report_json.hpp"
#include "epuck2/calibrate/report_text.hpp"
#include "epuck2/diagnose/extended_model.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/kind_facts.hpp"

namespace epuck2::diagnose {

namespace {

/// The kind's facts (lib/models kind_facts.hpp): every kind of log has them.
const models::KindFacts& facts_of(logs::Kind k) { return *models::kind_facts(std::string(logs::to_string(k))); }

/// The residuals' unit (the MSE's is its square): the unit of the kind's first channel, the one
/// the held-out MSEs are in.
std::string residual_unit(logs::Kind k) { return facts_of(k).channels.front().unit; }

/// The MSE's unit, naming the channel when the kind has several ("mm^2 (ToF)").
std::string units_of(logs::Kind k) {
  const models::KindFacts& f = facts_of(k);
  return residual_unit(k) + "^2" + (f.channels.size() > 1 ? std::string(" (") + f.channels.front().label + ")" : "");
}

/// A parameter's unit: a covariate's slope per unit of its column; a catalogue parameter's from
/// the effect registry (lib/models effects.hpp; "counts" are the kind's reading unit); a base
/// coefficient's from the kind's facts (named as its key, or as key_UNIT: gamma_m); else "1".
std::string parameter_unit(logs::Kind kind, const std::string& name) {
  const std::string base = name.substr(0, name.find('['));
  if (base == "slope") return residual_unit(kind) + " per unit of the column";
  if (const auto* c = models::effects::catalogue(std::string(logs::to_string(kind))))
    for (const auto& e : *c)
      if (const auto* p = e.param(base)) return std::string(p->unit) == "counts" ? residual_unit(kind) : p->unit;
  for (const models::BaseParam& p : facts_of(kind).base)
    if (base == p.key || base == std::string(p.key) + "_" + p.unit) return p.unit;
  return "1";
}

/// How the diagnosis fits, in words (the loss and the censoring).
const char* kDiagnosisLoss =
    "the calibration's censored (Tobit) likelihood (a reading on a rail enters by its probability of lying at or "
    "beyond it), each channel's residuals weighted by the reading's noise sd over its own";

/// What a cause means, in plain words: the registry's meaning (lib/models effects.hpp), or a
/// covariate's column, or a renamed finding's.
std::string meaning(logs::Kind kind, const std::string& cause) {
  if (cause.rfind(models::effects::kCovariatePrefix, 0) == 0)
    return "the readings drift with the column " + cause.substr(std::string(models::effects::kCovariatePrefix).size());
  if (const auto* c = models::effects::catalogue(std::string(logs::to_string(kind))))
    if (const auto* e = models::effects::find(*c, cause)) return e->meaning;
  return finding_meaning(cause);
}

/// Parameters named "gains[3]" become arrays (null where a sensor was not seen or is the reference).
void put_parameters(const std::vector<NamedValue>& values, nlohmann::json& value_out, nlohmann::json& error_out,
                    nlohmann::json* corrected_out = nullptr, nlohmann::json* jackknife_out = nullptr) {
  value_out = nlohmann::json::object();
  error_out = nlohmann::json::object();
  nlohmann::json corrected = nlohmann::json::object(), jackknife = nlohmann::json::object();
  const auto number = calibrate::json_number;  // null for NaN and infinity
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
std::string format_value(logs::Kind kind, const NamedValue& v) {
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
nlohmann::json rounded(logs::Kind kind, const std::vector<NamedValue>& values) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& v : values) j[v.name] = format_value(kind, v).substr(v.name.size() + 3);
  return j;
}

/// {name: why} for the standard errors written as null (the data do not determine them); empty
/// when there is none.
nlohmann::json undefined_errors(const std::vector<NamedValue>& values) {
  nlohmann::json why = nlohmann::json::object();
  for (const auto& v : values)
    if (!std::isfinite(v.std_error)) why[v.name] = v.std_error_why.empty() ? std::string("undefined") : v.std_error_why;
  return why;
}

std::string format_parameters(logs::Kind kind, const std::vector<NamedValue>& values) {
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

}  // namespace

nlohmann::json report_json(const Report& r, const std::vector<std::string>& paths, const ModelInputs& inputs) {
  nlohmann::json j;
  j["kind"] = std::string(logs::to_string(r.kind));
  j["rows"] = r.rows;
  j["residuals"] = r.residuals;
  std::vector<std::string> taken = paths;  // in the order the diagnosis took them
  std::stable_sort(taken.begin(), taken.end(), taken_before);
  j["logs"] = taken;
  j["verdict"] = r.verdict_name();
  if (const Finding* d = r.dominant()) j["most_of_the_gain"] = d->cause;
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
    j["mse_plugin_reading"] = r.mse_plugin_reading;
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
  j["statistics_conventions"] = calibrate::statistics_conventions_json(calibrate::kDiagnosisResidualsConvention);
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
  j["mse_plugin_reading"] = r.mse_plugin_reading;
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
  auto scores = [](const std::vector<CovariateScore>& s) {
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
  const nlohmann::json model = extended_model_json(r, inputs);
  nlohmann::json fb, fb_se;
  put_parameters(r.final_base.empty() ? r.recalibrated : r.final_base, fb, fb_se);
  j["final_base"] = fb;
  for (const auto& [key, value] : model.items())
    if (key != "kind") j[key] = value;
  return j;
}

std::string report_text(const Report& r, const std::string& base_name) {
  calibrate::Text out;
  const std::string u = fit::pretty_unit(units_of(r.kind));
  out("Diagnosis of %zu %s rows (%zu residuals)\n", r.rows, std::string(logs::to_string(r.kind)).c_str(), r.residuals);
  out("%s, before recalibration: MSE %.4g %s against its expected reading E[clamp(model + noise)]%s; %.4g %s against its "
      "reading as `simulate --like` writes it.\n",
      base_name.c_str(), r.heldout_mse_plugin, u.c_str(), r.too_few_rows ? "" : ", as every held-out MSE below",
      r.mse_plugin_reading, u.c_str());
  if (r.too_few_rows) {
    const std::string m = r.message.empty() ? r.message : std::string(1, static_cast<char>(std::toupper(r.message[0]))) + r.message.substr(1);
    out("%s.\nNo effect was judged: no recalibration, no search, no finding.\n", m.c_str());
    if (!r.outliers.empty()) out("Wild readings left out before the diagnosis: %zu\n", r.outliers.size());
    out("Verdict: %s\n", r.verdict_name().c_str());
    return out.str();
  }
  if (!r.channel_noise_sd.empty()) {
    out("Channels fitted together, each weighted by its noise:");
    for (const auto& c : r.channel_noise_sd) out(" %s (sd %.3g)", c.name.c_str(), c.value);
    out("; held-out MSEs below are the %s's.\n", r.channel_noise_sd.front().name.c_str());
  }
  const std::string ru = residual_unit(r.kind);
  out("Loss: %s. Readings on a rail: %zu at or below the low one, %zu at or above the high one.\n", kDiagnosisLoss,
      r.censored_below, r.censored_above);
  if (!r.recalibrated.empty())
    out("Recalibrated base model (%s): held-out MSE %.4g %s. This is what recalibration alone fixes, not an effect.\n",
        format_parameters(r.kind, r.recalibrated).c_str(), r.heldout_mse_base, u.c_str());
  else
    out("The base model has no free parameter: held-out MSE %.4g %s.\n", r.heldout_mse_base, u.c_str());
  out("  fit to all rows: %s\n", format_statistics(r.base_fit, ru).c_str());
  if (!r.structure_before.empty() && r.structure_before.front().significant)
    out("Its residuals depend most on %s (%.0f %% of their variance).\n", r.structure_before.front().covariate.c_str(),
        100 * r.structure_before.front().score);
  for (const auto& f : r.findings) {
    out("Finding: %s (%s); %s explains it; held-out MSE %.4g -> %.4g %s", f.cause.c_str(), meaning(r.kind, f.cause).c_str(),
        format_parameters(r.kind, f.parameters).c_str(), f.heldout_mse_before, f.heldout_mse_after, u.c_str());
    if (!r.channel_noise_sd.empty())
      out(", all channels weighted %.4g -> %.4g", f.heldout_weighted_before, f.heldout_weighted_after);
    if (f.accepted_with.empty()) out(" (BIC %+.1f).\n", f.delta_bic);
    else out(" (BIC %+.1f, the pair's: accepted together with %s).\n", f.delta_bic, f.accepted_with.c_str());
    out("  fit to all rows with it: %s\n", format_statistics(f.fit, ru).c_str());
  }
  if (r.findings.size() > 1) {
    out("Most of the gain: %s (taken out of the final model, the BIC rises by", r.dominant()->cause.c_str());
    for (const auto& f : r.findings) out(" %s %+.1f", f.cause.c_str(), f.removal_delta_bic);
    out(").\n");
  }
  for (const auto& f : r.possible)
    out("%s: %s (%s): %s; left out of the extended model.\n", f.outside_physical_range ? "Not written" : "Possible, not determined", f.cause.c_str(),
        meaning(r.kind, f.cause).c_str(), f.undetermined.c_str());
  for (const auto& f : r.findings)
    if (!f.alternatives.empty()) {
      std::string alts;
      for (const auto& a : f.alternatives) alts += (alts.empty() ? "" : ", ") + a;
      out("Note: these logs cannot tell %s from %s (they fit almost as well).\n", f.cause.c_str(), alts.c_str());
    }
  for (const auto& n : r.notes) out("Note: %s.\n", n.c_str());
  if (r.censored > 0) out("Readings on a sensor's rails: %zu (censored: the Tobit likelihood).\n", r.censored);
  if (!r.outliers.empty()) {
    out("Wild readings left out before the diagnosis: %zu\n", r.outliers.size());
    for (std::size_t k = 0; k < r.outliers.size() && k < 5; ++k) out("  %s\n", r.outliers[k].c_str());
  }
  if (r.findings.empty()) out("No effect of the catalogue passes both the BIC and the held-out test.\n");
  // The base's parameters move when the findings are fitted with them: the extended model (the
  // JSON's final_base) holds these, not the recalibration's above.
  if (!r.findings.empty() && !r.final_base.empty())
    out("Base model in the final fit, with the findings (the extended model's): %s.\n",
        format_parameters(r.kind, r.final_base).c_str());
  out("Final model: %s (AIC n ln(RSS/n) + 2k, BIC n ln(RSS/n) + k ln n, as lmfit", format_statistics(r.final_fit, ru).c_str());
  out("%s)\n", r.channel_noise_sd.empty() ? "" : "; residuals weighted by their channel's noise, in the first channel's units");
  out("  correlations (|r| > 0.1):");
  if (r.correlations.empty()) out(" none");
  for (std::size_t k = 0; k < r.correlations.size(); ++k)
    out("%s %s-%s %+.3f", k ? "," : "", r.correlations[k].a.c_str(), r.correlations[k].b.c_str(), r.correlations[k].r);
  out("\n");
  if (r.time_series) {
    const auto& a = r.autocorrelation;
    if (a.computed)
      out("  a log's rows are a time series: the residuals' lag-1 autocorrelation %.5f (%s) gives AR(1) "
          "n_eff = n (1-rho)/(1+rho) = %.4g of %zu, factor %.3g\n",
          a.rho, r.autocorrelation_channel.c_str(), a.n_eff, a.n, a.factor);
    else
      out("  a log's rows are a time series, but the residuals' lag-1 autocorrelation was not estimated (%s)\n",
          a.why_not.c_str());
    if (a.cluster_robust)
      out("  [corrected for autocorrelation] errors: cluster-robust with each of the %zu logs a cluster (sandwich, "
          "G/(G-1)), never below the covariance's: a misfit that lasts a whole log counts once per log\n",
          a.series);
    else
      out("  [corrected for autocorrelation] errors: the covariance's times the AR(1) factor (not cluster-robust: %s)\n",
          a.cluster_why_not.c_str());
  }
  for (const auto& w : r.warnings) out("Warning: %s\n", w.c_str());
  out("Residual structure left:");
  for (std::size_t k = 0; k < r.structure_after.size() && k < 4; ++k)
    out(" %s %.3f%s", r.structure_after[k].covariate.c_str(), r.structure_after[k].score,
        r.structure_after[k].significant ? " (significant)" : "");
  out("\nVerdict: %s", r.verdict_name().c_str());
  if (r.verdict == Verdict::unexplained)
    out(" (the residuals%s still depend on %s, which no effect of the catalogue explains)",
        r.structure_after.front().channel.empty() ? "" : (" of " + r.structure_after.front().channel).c_str(),
        r.structure_after.front().covariate.c_str());
  out("\n");
  return out.str();
}

}  // namespace epuck2::diagnose
