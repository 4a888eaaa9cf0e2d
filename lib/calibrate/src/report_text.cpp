#include "epuck2/calibrate/report_text.hpp"

#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "epuck2/calibrate/report_json.hpp"

namespace epuck2::calibrate {

void Text::operator()(const char* format, ...) {
  va_list args, again;
  va_start(args, format);
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  if (n > 0) {
    const std::size_t at = text_.size();
    text_.resize(at + static_cast<std::size_t>(n) + 1);
    std::vsnprintf(&text_[at], static_cast<std::size_t>(n) + 1, format, again);
    text_.resize(at + static_cast<std::size_t>(n));
  }
  va_end(again);
}

void write_statistics(Text& out, const fit::FitStatistics& s, const std::string& unit, const char* indent) {
  const std::string u = unit.empty() ? "" : " " + fit::pretty_unit(unit + "^2");
  char r2[48];
  if (std::isfinite(s.r2)) std::snprintf(r2, sizeof r2, "%.6f", s.r2);
  else std::snprintf(r2, sizeof r2, "undefined (the data do not vary)");
  out("%sn %zu, k %d free parameters, RSS %.4g%s, MSE %.4g%s, reduced χ² = RSS/(n-k) %.4g%s, R² %s\n", indent, s.n, s.k,
              s.rss, u.c_str(), s.mse, u.c_str(), s.reduced_chi2, u.c_str(), r2);
  out("%s%s (n ln(RSS/n) + 2k and + k ln n, as lmfit)\n", indent, fit::format_information_criteria(s, 2).c_str());
}

void write_correlations(Text& out, const std::vector<fit::Correlation>& c, const char* indent) {
  if (c.empty()) {
    out("%scorrelations: none with |r| > 0.1\n", indent);
    return;
  }
  out("%scorrelations (|r| > 0.1):", indent);
  for (std::size_t i = 0; i < c.size(); ++i) out("%s %s-%s %+.3f", i ? "," : "", c[i].a.c_str(), c[i].b.c_str(), c[i].r);
  out("\n");
}

void write_autocorrelation(Text& out, const fit::AutocorrelationCorrection& a, const char* indent) {
  if (a.computed)
    out("%sresiduals' lag-1 autocorrelation %.4f within runs: AR(1) n_eff = n (1-rho)/(1+rho) = %.4g of %zu, factor %.3g\n",
                indent, a.rho, a.n_eff, a.n, a.factor);
  else
    out("%sresiduals' lag-1 autocorrelation not estimated (%s)\n", indent, a.why_not.c_str());
  if (a.cluster_robust)
    out("%s[corrected] errors: cluster-robust with each of the %zu runs a cluster (sandwich, G/(G-1)), never below the "
                "covariance's\n", indent, a.series);
  else
    out("%s[corrected] errors: the covariance's times the AR(1) factor (not cluster-robust: %s)\n", indent,
                a.cluster_why_not.c_str());
}

void write_handling(Text& out, const fit::RobustFit& r, const std::string& unit, const char* indent,
                    const fit::AutocorrelationCorrection* autocorrelation, bool has_rails) {
  std::string method = r.method;
  const std::string censoring = "; readings on a rail censored (Tobit)";
  if (const std::size_t at = method.find(censoring); !has_rails && at != std::string::npos) method.erase(at, censoring.size());
  out("%s%s\n", indent, method.c_str());
  if (has_rails)
    out("%s%zu observations: %zu inside the rails, %zu censored (%zu at or below the low rail, %zu at or above the high), "
                "%zu outliers left out\n",
                indent, r.observations + r.outliers.size(), r.exact, r.censored(), r.censored_below, r.censored_above,
                r.outliers.size());
  else
    out("%s%zu observations (no rails: none censored), %zu outliers left out\n", indent,
                r.observations + r.outliers.size(), r.outliers.size());
  for (std::size_t i = 0; i < r.outlier_where.size() && i < 5; ++i) out("%s  outlier: %s\n", indent, r.outlier_where[i].c_str());
  if (r.outlier_where.size() > 5) out("%s  ... and %zu more (all in the JSON)\n", indent, r.outlier_where.size() - 5);
  const std::string sd_unit = unit.empty() ? "" : " " + fit::pretty_unit(unit);
  if (has_rails)
    out("%skept: %zu inside the rails (the RSS's n), %zu at or below the low rail, %zu at or above the high; noise sd %.4g%s\n",
                indent, r.kept_exact, r.kept_censored_below, r.kept_censored_above, r.noise_sd, sd_unit.c_str());
  else
    out("%skept: %zu (the RSS's n); noise sd %.4g%s\n", indent, r.kept_exact, r.noise_sd, sd_unit.c_str());
  write_statistics(out, robust_statistics(r), unit, indent);
  if (has_rails)
    out("%sTobit likelihood (censored readings included, sigma estimated): ln L %.2f, AIC %.2f, BIC %.2f "
                "(-2 ln L + 2(k+1) and + (k+1) ln n)\n",
                indent, r.log_likelihood, r.aic, r.bic);
  write_correlations(out, fit::correlations(r), indent);
  if (autocorrelation != nullptr) write_autocorrelation(out, *autocorrelation, indent);
  if (r.lack_of_fit.tested)
    out("%slack of fit against %zu replicate groups: reduced χ² against the replicates' noise %.3g (p = %.3g), replicate sd %.4g%s\n", indent,
                r.lack_of_fit.groups, r.lack_of_fit.reduced_chi2, r.lack_of_fit.p_value, r.lack_of_fit.replicate_sd,
                r.lack_of_fit.robots > 1
                    ? (" (the groups pool " + std::to_string(r.lack_of_fit.robots) +
                       " robots: this sd holds their differences beside the reading noise, and the curve is judged as their average)")
                          .c_str()
                    : "");
  if (r.lack_of_fit.tested)
    out("%smisfit %.3g replicate sd per reading (warning above %g, exit 1 above %g); worst: %s\n", indent,
                r.lack_of_fit.misfit_ratio, fit::kMisfitWarnRatio, fit::kMisfitFailRatio, r.lack_of_fit.worst.c_str());
  for (const auto& n : r.not_identifiable) {
    const auto why = r.std_error_why.find(n);
    out("%snot identifiable: %s (%s)\n", indent, n.c_str(), why == r.std_error_why.end() ? "" : why->second.c_str());
  }
}

void write_noise(Text& out, const ReadingNoise& n) {
  if (!n.usable()) {
    out("\nReading noise (%s): not measured\n", n.channel.c_str());
    return;
  }
  out("\nReading noise (%s): sd %.4g %s, from %s (%zu readings", n.channel.c_str(), n.sd, n.unit.c_str(),
              n.from.c_str(), n.n);
  if (n.from == "replicates") out(" in %zu groups", n.groups);
  out(")");
  if (n.argos_scale > 0) out("; ARGoS uniform noise_level of the same variance %.4g", n.argos_uniform_level());
  out("\n");
  bool any = false;
  for (std::size_t i = 0; i < n.per_sensor_sd.size(); ++i)
    if (n.per_sensor_n[i] > 0) {
      out("%s sensor %zu: %.4g (%zu)", any ? "," : "  per sensor (readings):", i, n.per_sensor_sd[i], n.per_sensor_n[i]);
      any = true;
    }
  if (any) out("; sensors without readings take the pooled sd\n");
}

void write_noise_sections(Text& out, const std::vector<ReadingNoise>& channels) {
  for (const auto& n : channels) write_noise(out, n);
}

void write_parameter(Text& out, const fit::RobustFit& r, const std::string& name, const std::string& unit,
                     const char* indent, const std::string& note,
                     const fit::AutocorrelationCorrection* autocorrelation) {
  const double v = r.value(name), e = r.std_error(name);
  const bool has_error = std::isfinite(e) && e > 0;
  const std::string why = has_error ? "" : std::isfinite(e) ? "held fixed" : "no standard error: " + std_error_reason(r, name);
  std::string line = name + " = " + fit::format_uncertain(v, e, fit::pretty_unit(unit), why);
  if (has_error && autocorrelation != nullptr && autocorrelation->std_error(name) > e)
    line += " [corrected ± " + fit::format_error(autocorrelation->std_error(name)) + "]";
  if (!note.empty()) line += " (" + note + ")";
  out("%s%s\n", indent, line.c_str());
}

}  // namespace epuck2::calibrate
