// The sensor subcommands' shared code (apps/sensor_support.hpp): compiled once here rather than
// in every cmd_<sensor>.cpp that includes the header.
#include "sensor_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>

namespace epuck2::app::sensors {

void add_common_options(CLI::App* sub, SensorOptions& o, const std::string& what) {
  sub->add_option("logs", o.logs, what + " logs (CSV, docs/logs.md)")->required()->check(CLI::ExistingFile);
  sub->add_flag("--json", o.json, "Print one JSON object instead of the report");
  sub->add_option("-o,--output", o.output, "Write the coefficient file (JSON), atomically")->type_name("FILE")->check(output_file());
  sub->add_option("--plot", o.plot,
                  "Draw the data, the fitted curve and the plug-in's curve to FILE (.png, .svg or .pdf, by the extension)")
      ->type_name("FILE")
      ->check(figure_file())
      ->check(output_file());
  add_figure_options(sub);
  sub->add_flag("--least-squares", o.least_squares,
                "Plain least squares: no reading is left out as an outlier (readings on a rail stay censored)");
  sub->add_option("--reject-sd", o.reject_sd, "Robust fits: readings farther than this many noise sd are outliers")
      ->check(CLI::Range(2.0, 100.0));
  sub->add_option("--robot", o.robot, "Fit only this robot's logs (# robot: metadata, a robot column, or the file name)");
  add_skip_bad_rows(sub, o.skip_bad_rows);
  sub->add_flag("--accept-misfit", o.accept_misfit,
                "Write the calibration even when a fit misses its data by many times its replicate noise or its R^2 is "
                "below the floor (a warning instead of exit 1; docs/fitting.md)");
}

std::vector<logs::Log> select_robot(std::vector<logs::Log> all, const std::string& robot) {
  if (robot.empty()) return all;
  std::vector<logs::Log> out;
  std::vector<std::string> names;
  for (auto& l : all) {
    if (std::find(names.begin(), names.end(), l.robot) == names.end()) names.push_back(l.robot);
    if (l.robot == robot) out.push_back(std::move(l));
  }
  if (out.empty()) {
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    throw UsageError("--robot " + robot + ": no log of that robot; these logs are of " + list);
  }
  return out;
}

std::vector<std::string> robots_of(const std::vector<logs::Log>& all) {
  std::vector<std::string> names;
  for (const auto& l : all)
    if (std::find(names.begin(), names.end(), l.robot) == names.end()) names.push_back(l.robot);
  return names;
}

nlohmann::json skeleton(const std::string& kind, const std::vector<logs::Log>& logs) {
  std::vector<std::string> sources;
  for (const auto& l : logs) sources.push_back(l.path);
  nlohmann::json j;
  j["kind"] = kind;
  j["parameters"] = nlohmann::json::object();
  j["std_errors"] = nlohmann::json::object();
  j["sources"] = sources;
  return j;
}

nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

void append(nlohmann::json& j, const std::string& key, const nlohmann::json& v) {
  if (!j.contains(key)) j[key] = nlohmann::json::array();
  j[key].push_back(v);
}

nlohmann::json fit_details(const fit::RobustFit& r, const std::string& rss_unit,
                           const fit::AutocorrelationCorrection* autocorrelation) {
  nlohmann::json d = calibrate::statistics_json(calibrate::robust_statistics(r), rss_unit);
  d["method"] = r.method;
  d["observations"] = r.observations;
  d["inside_rails"] = r.exact;
  d["censored"] = {{"at_or_below", r.censored_below}, {"at_or_above", r.censored_above}};
  d["censored_kept"] = {{"at_or_below", r.kept_censored_below}, {"at_or_above", r.kept_censored_above}};
  d["outliers"] = r.outliers.size();
  d["noise_sd"] = number(r.noise_sd);
  if (!std::isfinite(r.r2)) d["r2_why"] = "the readings inside the rails do not vary: there is no variance to explain";
  d["log_likelihood"] = number(r.log_likelihood);
  d["aic_likelihood"] = number(r.aic);
  d["bic_likelihood"] = number(r.bic);
  d["correlations"] = calibrate::correlations_json(fit::correlations(r));
  if (autocorrelation != nullptr) d["autocorrelation"] = calibrate::autocorrelation_json(*autocorrelation);
  if (r.lack_of_fit.tested)
    d["lack_of_fit"] = {{"reduced_chi2", number(r.lack_of_fit.reduced_chi2)}, {"p_value", number(r.lack_of_fit.p_value)},
                        {"replicate_sd", number(r.lack_of_fit.replicate_sd)}, {"groups", r.lack_of_fit.groups},
                        {"dof_lack", r.lack_of_fit.dof_lack}, {"dof_pure", r.lack_of_fit.dof_pure},
                        {"misfit_rms", number(r.lack_of_fit.misfit_rms)}, {"misfit_ratio", number(r.lack_of_fit.misfit_ratio)},
                        {"worst", r.lack_of_fit.worst}};
  else
    d["lack_of_fit"] = {{"tested", false}, {"why", r.lack_of_fit.why_not}};
  return d;
}

void add_aggregates(nlohmann::json& j, const fit::RobustFit& r, const std::string& key, const std::string& prefix,
                    const std::string& rss_unit, const fit::AutocorrelationCorrection* autocorrelation) {
  for (const auto& n : r.not_identifiable) append(j, "not_identifiable", prefix + n);
  j["fits"][key] = fit_details(r, rss_unit, autocorrelation);
  if (!j.contains("statistics_conventions")) j["statistics_conventions"] = calibrate::statistics_conventions_json();
  if (!j.contains("correlations")) j["correlations"] = nlohmann::json::array();
  for (const auto& c : calibrate::correlations_json(fit::correlations(r), prefix)) j["correlations"].push_back(c);
  // Only the parameters with a standard error to correct (the others' reasons: std_error_why).
  if (autocorrelation != nullptr)
    for (const auto& p : r.parameters)
      if (std::isfinite(autocorrelation->std_error(p.name)))
        j["std_errors_corrected"][prefix + p.name] = autocorrelation->std_error(p.name);
  j["censored"] = j.value("censored", std::size_t{0}) + r.censored();
  if (!j.contains("outliers")) j["outliers"] = {{"count", 0}, {"rows", nlohmann::json::array()}};
  j["outliers"]["count"] = j["outliers"]["count"].get<std::size_t>() + r.outlier_where.size();
  for (const auto& w : r.outlier_where) j["outliers"]["rows"].push_back(w);
  if (r.lack_of_fit.tested) j["lack_of_fit"][key] = j["fits"][key]["lack_of_fit"];
}

std::string std_error_reason(const fit::RobustFit& r, const std::string& name) {
  const auto why = r.std_error_why.find(name);
  if (why != r.std_error_why.end()) return why->second;
  for (const auto& p : r.parameters)
    if (p.name == name && !p.std_error_why.empty()) return p.std_error_why;
  return "the covariance could not be computed";
}

std::string unit_of(const nlohmann::json& j, const std::string& name) {
  if (!j.contains("units")) return "";
  const std::string base = name.substr(0, name.find('['));  // gain[0]: the unit of gain
  for (const std::string& key : {name, base})
    if (j["units"].contains(key) && j["units"][key].is_string()) return j["units"][key].get<std::string>();
  return "";
}

void add_rounded(nlohmann::json& j, const std::string& name, double value, double std_error, const std::string& why) {
  const std::string unit = unit_of(j, name);
  j["rounded"][name] = fit::format_uncertain(value, std_error, unit == "1" ? "" : unit, why);  // a ratio: no unit
}

void add_parameters(nlohmann::json& j, const fit::RobustFit& r, const std::string& prefix,
                    const std::string& key, const std::string& rss_unit,
                    const fit::AutocorrelationCorrection* autocorrelation) {
  for (const auto& p : r.parameters) {
    j["parameters"][prefix + p.name] = number(p.value);
    j["std_errors"][prefix + p.name] = number(p.std_error);
    const bool has_error = std::isfinite(p.std_error) && p.std_error > 0;
    if (!std::isfinite(p.std_error)) j["std_error_why"][prefix + p.name] = std_error_reason(r, p.name);
    add_rounded(j, prefix + p.name, p.value, p.std_error,
                has_error ? "" : std::isfinite(p.std_error) ? "held fixed" : std_error_reason(r, p.name));
  }
  add_aggregates(j, r, key, prefix, rss_unit, autocorrelation);
}

void add_left_out(nlohmann::json& j, const std::vector<calibrate::LeftOut>& rows) {
  if (!j.contains("outliers")) j["outliers"] = {{"count", 0}, {"rows", nlohmann::json::array()}};
  nlohmann::json list = nlohmann::json::array();
  for (const auto& r : rows) {
    list.push_back({{"where", r.where}, {"why", r.why}});
    if (r.why.rfind("wild", 0) == 0) {
      j["outliers"]["count"] = j["outliers"]["count"].get<std::size_t>() + 1;
      j["outliers"]["rows"].push_back(r.where);
    }
  }
  j["left_out"] = {{"count", rows.size()}, {"rows", list}};
}

void add_noise(nlohmann::json& j, const std::vector<calibrate::ReadingNoise>& channels) {
  nlohmann::json section = nlohmann::json::object();
  for (const auto& c : channels) {
    if (!c.usable())
      throw NoUsableFit(c.channel + " reading noise: no reading to measure it from (" +
                        (c.from == "replicates" ? "no group of two or more readings under the same conditions inside the rails"
                                                : "the fit it comes from is not usable") +
                        ")");
    nlohmann::json e = {{"sd", c.sd}, {"unit", c.unit}, {"from", c.from}, {"n", c.n}};
    if (c.from == "replicates") e["groups"] = c.groups;
    if (!c.per_sensor_sd.empty()) {
      e["per_sensor_sd"] = c.per_sensor_sd;
      e["per_sensor_n"] = c.per_sensor_n;
    }
    if (c.argos_scale > 0) e["argos_uniform_level"] = c.argos_uniform_level();
    section[c.channel] = e;
  }
  j["noise"] = section;
}

void add_warnings(nlohmann::json& j, const std::vector<std::string>& warnings) {
  if (!j.contains("warnings")) j["warnings"] = nlohmann::json::array();
  for (const auto& w : warnings) j["warnings"].push_back(w);
}

void add_robots(nlohmann::json& j, const std::vector<logs::Log>& all,
                const std::function<nlohmann::json(const std::vector<logs::Log>&)>& fit_logs) {
  const std::vector<std::string> names = robots_of(all);
  if (names.size() < 2) return;
  std::map<std::string, std::vector<std::pair<double, double>>> by_parameter;  // value, se per robot
  for (const auto& name : names) {
    std::vector<logs::Log> mine;
    std::vector<std::string> files;
    for (const auto& l : all)
      if (l.robot == name) {
        mine.push_back(l);
        files.push_back(l.path);
      }
    nlohmann::json r;
    try {
      r = fit_logs(mine);
    } catch (const NoUsableFit& e) {
      j["robots"][name] = {{"logs", files}, {"usable", false}, {"why", e.what()}};
      continue;
    }
    j["robots"][name] = {{"logs", files}, {"usable", true}, {"parameters", r["parameters"]}, {"std_errors", r["std_errors"]}};
    if (r.contains("noise")) j["robots"][name]["noise"] = r["noise"];
    if (r.contains("not_identifiable")) j["robots"][name]["not_identifiable"] = r["not_identifiable"];
    for (auto it = r["parameters"].begin(); it != r["parameters"].end(); ++it) {
      const auto& se = r["std_errors"].value(it.key(), nlohmann::json());
      if (it->is_number() && se.is_number()) by_parameter[it.key()].push_back({it->get<double>(), se.get<double>()});
      if (it->is_array() && se.is_array())
        for (std::size_t i = 0; i < it->size() && i < se.size(); ++i)
          if ((*it)[i].is_number() && se[i].is_number())
            by_parameter[it.key() + "[" + std::to_string(i) + "]"].push_back({(*it)[i].get<double>(), se[i].get<double>()});
    }
  }
  nlohmann::json spread = nlohmann::json::array();
  for (const auto& [name, values] : by_parameter) {
    std::vector<fit::FitResult> fits(values.size());
    std::vector<const fit::FitResult*> ptrs;
    for (std::size_t i = 0; i < values.size(); ++i) {
      fits[i].usable = true;
      fits[i].parameters = {{name, values[i].first, values[i].second}};
      ptrs.push_back(&fits[i]);
    }
    for (const fit::RobotSpread& s : fit::robot_spread(ptrs)) {
      spread.push_back({{"parameter", name}, {"spread_sd", number(s.spread_sd)}, {"q", number(s.q)}, {"dof", s.dof},
                        {"p_value", number(s.p_value)}, {"exceeds_uncertainty", s.exceeds}});
      if (s.exceeds) {
        char buf[300];
        std::snprintf(buf, sizeof buf,
                      "the robots differ in %s beyond their own uncertainties (sd between robots %.4g, Q = %.3g, p = %.2g): "
                      "the pooled value describes no robot; use `robots` or --robot ID.",
                      name.c_str(), s.spread_sd, s.q, s.p_value);
        append(j, "warnings", std::string(buf));
      }
    }
  }
  j["robot_spread"] = spread;
}

void print_statistics(const fit::FitStatistics& s, const std::string& unit, const char* indent) {
  const std::string u = unit.empty() ? "" : " " + fit::pretty_unit(unit + "^2");
  char r2[48];
  if (std::isfinite(s.r2)) std::snprintf(r2, sizeof r2, "%.6f", s.r2);
  else std::snprintf(r2, sizeof r2, "undefined (the data do not vary)");
  std::printf("%sn %zu, k %d free parameters, RSS %.4g%s, MSE %.4g%s, reduced χ² = RSS/(n-k) %.4g%s, R² %s\n", indent, s.n, s.k,
              s.rss, u.c_str(), s.mse, u.c_str(), s.reduced_chi2, u.c_str(), r2);
  std::printf("%s%s (n ln(RSS/n) + 2k and + k ln n, as lmfit)\n", indent, fit::format_information_criteria(s, 2).c_str());
}

void print_correlations(const std::vector<fit::Correlation>& c, const char* indent) {
  if (c.empty()) {
    std::printf("%scorrelations: none with |r| > 0.1\n", indent);
    return;
  }
  std::printf("%scorrelations (|r| > 0.1):", indent);
  for (std::size_t i = 0; i < c.size(); ++i) std::printf("%s %s-%s %+.3f", i ? "," : "", c[i].a.c_str(), c[i].b.c_str(), c[i].r);
  std::printf("\n");
}

void print_autocorrelation(const fit::AutocorrelationCorrection& a, const char* indent) {
  if (a.computed)
    std::printf("%sresiduals' lag-1 autocorrelation %.4f within runs: AR(1) n_eff = n (1-rho)/(1+rho) = %.4g of %zu, factor %.3g\n",
                indent, a.rho, a.n_eff, a.n, a.factor);
  else
    std::printf("%sresiduals' lag-1 autocorrelation not estimated (%s)\n", indent, a.why_not.c_str());
  if (a.cluster_robust)
    std::printf("%s[corrected] errors: cluster-robust with each of the %zu runs a cluster (sandwich, G/(G-1)), never below the "
                "covariance's\n", indent, a.series);
  else
    std::printf("%s[corrected] errors: the covariance's times the AR(1) factor (not cluster-robust: %s)\n", indent,
                a.cluster_why_not.c_str());
}

void print_handling(const fit::RobustFit& r, const std::string& unit, const char* indent,
                    const fit::AutocorrelationCorrection* autocorrelation, bool has_rails) {
  std::string method = r.method;
  const std::string censoring = "; readings on a rail censored (Tobit)";
  if (const std::size_t at = method.find(censoring); !has_rails && at != std::string::npos) method.erase(at, censoring.size());
  std::printf("%s%s\n", indent, method.c_str());
  if (has_rails)
    std::printf("%s%zu observations: %zu inside the rails, %zu censored (%zu at or below the low rail, %zu at or above the high), "
                "%zu outliers left out\n",
                indent, r.observations + r.outliers.size(), r.exact, r.censored(), r.censored_below, r.censored_above,
                r.outliers.size());
  else
    std::printf("%s%zu observations (no rails: none censored), %zu outliers left out\n", indent,
                r.observations + r.outliers.size(), r.outliers.size());
  for (std::size_t i = 0; i < r.outlier_where.size() && i < 5; ++i) std::printf("%s  outlier: %s\n", indent, r.outlier_where[i].c_str());
  if (r.outlier_where.size() > 5) std::printf("%s  ... and %zu more (all in the JSON)\n", indent, r.outlier_where.size() - 5);
  const std::string sd_unit = unit.empty() ? "" : " " + fit::pretty_unit(unit);
  if (has_rails)
    std::printf("%skept: %zu inside the rails (the RSS's n), %zu at or below the low rail, %zu at or above the high; noise sd %.4g%s\n",
                indent, r.kept_exact, r.kept_censored_below, r.kept_censored_above, r.noise_sd, sd_unit.c_str());
  else
    std::printf("%skept: %zu (the RSS's n); noise sd %.4g%s\n", indent, r.kept_exact, r.noise_sd, sd_unit.c_str());
  print_statistics(calibrate::robust_statistics(r), unit, indent);
  if (has_rails)
    std::printf("%sTobit likelihood (censored readings included, sigma estimated): ln L %.2f, AIC %.2f, BIC %.2f "
                "(-2 ln L + 2(k+1) and + (k+1) ln n)\n",
                indent, r.log_likelihood, r.aic, r.bic);
  print_correlations(fit::correlations(r), indent);
  if (autocorrelation != nullptr) print_autocorrelation(*autocorrelation, indent);
  if (r.lack_of_fit.tested)
    std::printf("%slack of fit against %zu replicate groups: reduced χ² against the replicates' noise %.3g (p = %.3g), replicate sd %.4g\n", indent,
                r.lack_of_fit.groups, r.lack_of_fit.reduced_chi2, r.lack_of_fit.p_value, r.lack_of_fit.replicate_sd);
  if (r.lack_of_fit.tested)
    std::printf("%smisfit %.3g replicate sd per reading (warning above %g, exit 1 above %g); worst: %s\n", indent,
                r.lack_of_fit.misfit_ratio, fit::kMisfitWarnRatio, fit::kMisfitFailRatio, r.lack_of_fit.worst.c_str());
  for (const auto& n : r.not_identifiable) {
    const auto why = r.std_error_why.find(n);
    std::printf("%snot identifiable: %s (%s)\n", indent, n.c_str(), why == r.std_error_why.end() ? "" : why->second.c_str());
  }
}

void print_noise(const calibrate::ReadingNoise& n) {
  if (!n.usable()) {
    std::printf("\nReading noise (%s): not measured\n", n.channel.c_str());
    return;
  }
  std::printf("\nReading noise (%s): sd %.4g %s, from %s (%zu readings", n.channel.c_str(), n.sd, n.unit.c_str(),
              n.from.c_str(), n.n);
  if (n.from == "replicates") std::printf(" in %zu groups", n.groups);
  std::printf(")");
  if (n.argos_scale > 0) std::printf("; ARGoS uniform noise_level of the same variance %.4g", n.argos_uniform_level());
  std::printf("\n");
  bool any = false;
  for (std::size_t i = 0; i < n.per_sensor_sd.size(); ++i)
    if (n.per_sensor_n[i] > 0) {
      std::printf("%s sensor %zu: %.4g (%zu)", any ? "," : "  per sensor (readings):", i, n.per_sensor_sd[i], n.per_sensor_n[i]);
      any = true;
    }
  if (any) std::printf("; sensors without readings take the pooled sd\n");
}

void print_noise_and_warnings(const std::vector<calibrate::ReadingNoise>& channels,
                              const std::vector<std::string>& warnings) {
  for (const auto& n : channels) print_noise(n);
  if (!warnings.empty()) std::printf("%zu warnings (on standard error and in the JSON)\n", warnings.size());
}

void print_parameter(const fit::RobustFit& r, const std::string& name, const std::string& unit,
                     const char* indent, const std::string& note,
                     const fit::AutocorrelationCorrection* autocorrelation) {
  const double v = r.value(name), e = r.std_error(name);
  const bool has_error = std::isfinite(e) && e > 0;
  const std::string why = has_error ? "" : std::isfinite(e) ? "held fixed" : "no standard error: " + std_error_reason(r, name);
  std::string line = name + " = " + fit::format_uncertain(v, e, fit::pretty_unit(unit), why);
  if (has_error && autocorrelation != nullptr && autocorrelation->std_error(name) > e)
    line += " [corrected ± " + fit::format_error(autocorrelation->std_error(name)) + "]";
  if (!note.empty()) line += " (" + note + ")";
  std::printf("%s%s\n", indent, line.c_str());
}

void print_warnings(const std::string& kind, const nlohmann::json& j) {
  if (!j.contains("warnings")) return;
  for (const auto& w : j["warnings"]) std::cerr << kind << ": warning: " << w.get<std::string>() << '\n';
}

void warn_undefined_std_errors(const std::string& kind, const nlohmann::json& j) {
  if (!j.contains("std_error_why")) return;
  for (const auto& [name, why] : j.at("std_error_why").items())
    std::cerr << kind << ": warning: no standard error for " << name << ": " << why.get<std::string>() << '\n';
}

void require_usable(const fit::FitResult& r, const std::string& what) {
  if (!r.usable) throw NoUsableFit(what + ": " + (r.message.empty() ? std::string("the solver found no solution") : r.message));
}

void require_fitting(const fit::RobustFit& r, const std::string& what, const SensorOptions& o,
                     std::vector<std::string>& warnings) {
  if (!r.usable) return;
  const std::string verdict = fit::misfit_verdict(r.lack_of_fit, r.r2);
  const std::string low_r2 = fit::misfit_warning(r.lack_of_fit, r.r2);
  if (!low_r2.empty()) warnings.push_back(what + ": " + low_r2 + ".");
  if (verdict.empty()) return;
  if (!o.accept_misfit)
    throw NoUsableFit(what + ": " + verdict + ". Nothing was written; --accept-misfit writes it anyway.");
  warnings.push_back(what + " (accepted by --accept-misfit): " + verdict + ".");
}

}  // namespace epuck2::app::sensors
