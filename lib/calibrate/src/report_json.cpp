#include "epuck2/calibrate/report_json.hpp"

#include <cmath>

namespace epuck2::calibrate {

using nlohmann::json;

json json_number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json statistics_json(const fit::FitStatistics& s, const std::string& rss_unit) {
  json j{{"n", s.n},
         {"free_parameters", s.k},
         {"rss", json_number(s.rss)},
         {"mse", json_number(s.mse)},
         {"reduced_chi2", json_number(s.reduced_chi2)},
         {"r2", json_number(s.r2)},
         {"aic", json_number(s.aic)},
         {"bic", json_number(s.bic)},
         {"rss_unit", rss_unit}};
  if (!std::isfinite(s.r2)) j["r2_why"] = "the data do not vary: there is no variance to explain";
  if (!std::isfinite(s.reduced_chi2)) j["reduced_chi2_why"] = "no degree of freedom left (n <= k)";
  if (!std::isfinite(s.aic)) j["aic_why"] = s.n == 0 ? "no residual" : fit::kInformationCriteriaUndefined;
  if (!std::isfinite(s.bic)) j["bic_why"] = s.n == 0 ? "no residual" : fit::kInformationCriteriaUndefined;
  return j;
}

json statistics_conventions_json() {
  return {{"n", "residuals in the RSS (readings inside the rails that the fit kept)"},
          {"reduced_chi2", fit::kReducedChi2Convention},
          {"aic", fit::kAicConvention},
          {"bic", fit::kBicConvention},
          {"correlations", "pairs with |r| > 0.1 (lmfit), r = cov(a, b) / (se_a se_b)"}};
}

json correlations_json(const std::vector<fit::Correlation>& c, const std::string& prefix) {
  json a = json::array();
  for (const auto& x : c) a.push_back({{"a", prefix + x.a}, {"b", prefix + x.b}, {"r", json_number(x.r)}});
  return a;
}

json autocorrelation_json(const fit::AutocorrelationCorrection& a) {
  json j{{"computed", a.computed}, {"method", a.method.empty() ? std::string(fit::kAutocorrelationMethod) : a.method},
         {"cluster_robust", a.cluster_robust}};
  if (a.computed) {
    j["rho"] = json_number(a.rho);
    j["n"] = a.n;
    j["n_eff"] = json_number(a.n_eff);
    j["factor"] = json_number(a.factor);
  } else {
    j["why"] = a.why_not;
  }
  j["series"] = a.series;
  if (!a.cluster_robust) j["cluster_robust_why_not"] = a.cluster_why_not;
  return j;
}

fit::FitStatistics robust_statistics(const fit::RobustFit& r) {
  return fit::fit_statistics(r.kept_exact, r.free_parameters, r.rss, r.r2);
}

}  // namespace epuck2::calibrate
