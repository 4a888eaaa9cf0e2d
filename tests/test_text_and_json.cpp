// The text report says what the JSON report says. For every sensor kind, on the shipped logs, through
// the real binary: each fit of the JSON's `fits` is found in the text by its n, k and RSS, and every
// other number of its block (observations, rails, outliers, what was kept, the noise sd, the
// statistics, the information criteria, the Tobit likelihood, the lack-of-fit test and the misfit)
// must be the JSON's, to the digits the text prints. The two are written by different code
// (lib/calibrate report_text.cpp and the kinds' reports; report_json.cpp): a slip in one -- a
// swapped argument, a wrong field -- shows as a disagreement.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace test_text_and_json_cpp {
namespace {

using nlohmann::json;

std::string capture(const std::string& cmd) {
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  EXPECT_NE(p, nullptr);
  if (!p) return out;
  char buf[65536];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  EXPECT_EQ(::pclose(p), 0) << cmd;
  return out;
}

/// One fit's block of the text report (std::nullopt: the line was not there).
struct Block {
  std::optional<double> observations, inside, censored, below, above, outliers;
  std::optional<double> kept, kept_below, kept_above, noise_sd;
  std::optional<double> n, k, rss, mse, reduced_chi2, r2;
  std::optional<double> aic, bic, log_l, aic_l, bic_l;
  std::optional<double> groups, lof_chi2, p, replicate_sd, misfit;
  bool rails = false;
};

double num(const std::string& s) { return std::strtod(s.c_str(), nullptr); }

std::vector<Block> blocks_of(const std::string& text) {
  static const std::regex obs(R"((\d+) observations: (\d+) inside the rails, (\d+) censored \((\d+) at or below the low rail, (\d+) at or above the high\), (\d+) outliers left out)");
  static const std::regex obs_free(R"((\d+) observations \(no rails: none censored\), (\d+) outliers left out)");
  static const std::regex kept(R"(kept: (\d+) inside the rails \(the RSS's n\), (\d+) at or below the low rail, (\d+) at or above the high; noise sd (\S+))");
  static const std::regex kept_free(R"(kept: (\d+) \(the RSS's n\); noise sd (\S+))");
  static const std::regex stat(R"(n (\d+), k (\d+) free parameters, RSS ([-+0-9.e]+).*, MSE ([-+0-9.e]+).*RSS/\(n-k\) ([-+0-9.e]+).*, R² ([-0-9.]+|undefined))");
  static const std::regex ic(R"(^\s*AIC ([-0-9.]+), BIC ([-0-9.]+) \(n ln)");
  static const std::regex tobit(R"(ln L ([-0-9.]+), AIC ([-0-9.]+), BIC ([-0-9.]+) \(-2 ln L)");
  static const std::regex lack(R"(lack of fit against (\d+) replicate groups: reduced χ² against the replicates' noise (\S+) \(p = (\S+)\), replicate sd (\S+))");
  static const std::regex misfit(R"(^\s*misfit (\S+) replicate sd per reading)");
  std::vector<Block> out;
  std::istringstream in(text);
  std::string line;
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_search(line, m, obs)) {
      out.emplace_back();
      Block& b = out.back();
      b.rails = true;
      b.observations = num(m[1]), b.inside = num(m[2]), b.censored = num(m[3]), b.below = num(m[4]), b.above = num(m[5]),
      b.outliers = num(m[6]);
      continue;
    }
    if (std::regex_search(line, m, obs_free)) {
      out.emplace_back();
      out.back().observations = num(m[1]), out.back().outliers = num(m[2]);
      continue;
    }
    if (out.empty()) continue;
    Block& b = out.back();
    if (std::regex_search(line, m, kept)) b.kept = num(m[1]), b.kept_below = num(m[2]), b.kept_above = num(m[3]), b.noise_sd = num(m[4]);
    else if (std::regex_search(line, m, kept_free)) b.kept = num(m[1]), b.noise_sd = num(m[2]);
    else if (std::regex_search(line, m, stat))
      b.n = num(m[1]), b.k = num(m[2]), b.rss = num(m[3]), b.mse = num(m[4]), b.reduced_chi2 = num(m[5]),
      b.r2 = m[6] == "undefined" ? NAN : num(m[6]);
    else if (std::regex_search(line, m, ic)) b.aic = num(m[1]), b.bic = num(m[2]);
    else if (std::regex_search(line, m, tobit)) b.log_l = num(m[1]), b.aic_l = num(m[2]), b.bic_l = num(m[3]);
    else if (std::regex_search(line, m, lack)) b.groups = num(m[1]), b.lof_chi2 = num(m[2]), b.p = num(m[3]), b.replicate_sd = num(m[4]);
    else if (std::regex_search(line, m, misfit)) b.misfit = num(m[1]);
  }
  return out;
}

/// `printed` is `value` written to `digits` significant digits.
void expect_sig(const std::optional<double>& printed, double value, int digits, const std::string& what) {
  ASSERT_TRUE(printed.has_value()) << what << ": not in the text";
  EXPECT_LE(std::abs(*printed - value), 0.51 * std::pow(10.0, -(digits - 1)) * std::abs(value) + 1e-300) << what << ": text " << *printed
                                                                                                          << ", JSON " << value;
}
/// `printed` is `value` written with `decimals` decimals.
void expect_dec(const std::optional<double>& printed, double value, int decimals, const std::string& what) {
  ASSERT_TRUE(printed.has_value()) << what << ": not in the text";
  EXPECT_LE(std::abs(*printed - value), 0.51 * std::pow(10.0, -decimals)) << what << ": text " << *printed << ", JSON " << value;
}
void expect_count(const std::optional<double>& printed, double value, const std::string& what) {
  ASSERT_TRUE(printed.has_value()) << what << ": not in the text";
  EXPECT_EQ(*printed, value) << what;
}

class TextAndJson : public ::testing::TestWithParam<const char*> {};

TEST_P(TextAndJson, EveryNumberOfEachFitsBlockIsTheJsons) {
  const std::string kind = GetParam();
  const std::string logs = std::string(EPUCK2_SOURCE_DIR) + "/data/raw/" + kind + "/*.csv";
  const std::string exe = EPUCK2_FIT_EXE;
  const std::string text = capture("'" + exe + "' " + kind + " " + logs + " 2>/dev/null");
  const json j = json::parse(capture("'" + exe + "' " + kind + " " + logs + " --json 2>/dev/null"));
  const std::vector<Block> blocks = blocks_of(text);
  ASSERT_FALSE(blocks.empty()) << text;
  ASSERT_TRUE(j.contains("fits"));
  std::size_t checked = 0;
  for (const auto& [name, f] : j["fits"].items()) {
    const std::string w = kind + " fit " + name;
    const Block* b = nullptr;
    for (const Block& c : blocks)
      if (c.n && *c.n == f["n"].get<double>() && c.k && *c.k == f["free_parameters"].get<double>() && c.rss &&
          std::abs(*c.rss - f["rss"].get<double>()) <= 6e-4 * std::abs(f["rss"].get<double>()))
        b = &c;
    ASSERT_NE(b, nullptr) << w << ": no block of the text has its n, k and RSS";
    ++checked;
    expect_count(b->observations, f["observations"].get<double>() + f["outliers"].get<double>(), w + " observations");
    expect_count(b->outliers, f["outliers"], w + " outliers");
    expect_count(b->kept, f["n"], w + " kept");
    expect_sig(b->noise_sd, f["noise_sd"], 4, w + " noise sd");
    expect_sig(b->mse, f["mse"], 4, w + " MSE");
    expect_sig(b->reduced_chi2, f["reduced_chi2"], 4, w + " reduced chi2");
    if (std::isfinite(f.value("r2", NAN))) expect_dec(b->r2, f["r2"], 6, w + " R2");
    expect_dec(b->aic, f["aic"], 2, w + " AIC");
    expect_dec(b->bic, f["bic"], 2, w + " BIC");
    if (b->rails) {
      expect_count(b->inside, f["inside_rails"], w + " inside the rails");
      expect_count(b->below, f["censored"]["at_or_below"], w + " censored below");
      expect_count(b->above, f["censored"]["at_or_above"], w + " censored above");
      expect_count(b->censored, f["censored"]["at_or_below"].get<double>() + f["censored"]["at_or_above"].get<double>(), w + " censored");
      expect_count(b->kept_below, f["censored_kept"]["at_or_below"], w + " kept below");
      expect_count(b->kept_above, f["censored_kept"]["at_or_above"], w + " kept above");
      expect_dec(b->log_l, f["log_likelihood"], 2, w + " ln L");
      expect_dec(b->aic_l, f["aic_likelihood"], 2, w + " Tobit AIC");
      expect_dec(b->bic_l, f["bic_likelihood"], 2, w + " Tobit BIC");
    }
    if (f.contains("lack_of_fit") && f["lack_of_fit"].contains("groups")) {
      const json& l = f["lack_of_fit"];
      expect_count(b->groups, l["groups"], w + " replicate groups");
      expect_sig(b->lof_chi2, l["reduced_chi2"], 3, w + " lack-of-fit chi2");
      expect_sig(b->p, l["p_value"], 3, w + " p");
      expect_sig(b->replicate_sd, l["replicate_sd"], 4, w + " replicate sd");
      expect_sig(b->misfit, l["misfit_ratio"], 3, w + " misfit");
    } else {
      EXPECT_FALSE(b->groups.has_value()) << w << ": a lack-of-fit line the JSON does not have";
    }
  }
  EXPECT_GE(checked, 1u);
}

INSTANTIATE_TEST_SUITE_P(Kinds, TextAndJson, ::testing::Values("proximity", "light", "ground", "camera", "drive"));


// ---- the diagnosis: its text report against its JSON report ----

/// The digits after the decimal point of a printed number ("61.40" 2, "2270" 0, "1.2e-05" by its
/// exponent: 6 with 2 significant digits).
double half_unit(const std::string& printed) {
  const std::size_t e = printed.find_first_of("eE");
  const std::string mant = printed.substr(0, e);
  const std::size_t dot = mant.find('.');
  const int decimals = dot == std::string::npos ? 0 : static_cast<int>(mant.size() - dot - 1);
  const int exponent = e == std::string::npos ? 0 : std::atoi(printed.c_str() + e + 1);
  return 0.5 * std::pow(10.0, exponent - decimals);
}

/// A finding's parameter in the JSON: "gains[1]" is element 1 of "gains".
double json_param(const json& obj, const std::string& name) {
  const std::size_t b = name.find('[');
  if (b == std::string::npos) return obj.at(name).get<double>();
  return obj.at(name.substr(0, b)).at(std::stoul(name.substr(b + 1))).get<double>();
}

class DiagnosisTextAndJson : public ::testing::TestWithParam<const char*> {};

// Each `Finding:` line against the JSON's findings, in order: the cause; each parameter's value and
// its first-named error, which is the largest of the covariance's, the jackknife's and the
// autocorrelation-corrected (to the digits printed); the held-out MSEs before and after (4
// significant digits) and the BIC's change (1 decimal). Then "Most of the gain" (the cause and
// every finding's removal BIC), the residual structure left (the covariates, scores and
// significance in the JSON's order) and the verdict.
TEST_P(DiagnosisTextAndJson, EveryFindingsNumbersAreTheJsons) {
  const std::string kind = GetParam();
  const std::string logs = std::string(EPUCK2_SOURCE_DIR) + "/data/raw/" + kind + "/*.csv";
  const std::string exe = EPUCK2_FIT_EXE;
  const std::string text = capture("'" + exe + "' diagnose " + logs + " 2>/dev/null");
  const json j = json::parse(capture("'" + exe + "' diagnose " + logs + " --json 2>/dev/null"));
  static const std::regex finding(R"(^Finding: (\S+) \()");
  static const std::regex param(R"((?:; |, )([A-Za-z_0-9]+(?:\[\d+\])?) = ([-0-9.e+]+) ± ([0-9.e+-]+))");
  static const std::regex mse(R"(held-out MSE ([0-9.e+-]+) -> ([0-9.e+-]+) .*\(BIC ([-0-9.]+)\)\.?$)");
  std::istringstream in(text);
  std::string line;
  std::smatch m;
  std::size_t k = 0;
  std::string most, structure, verdict;
  while (std::getline(in, line)) {
    if (line.rfind("Most of the gain: ", 0) == 0) most = line;
    if (line.rfind("Residual structure left: ", 0) == 0) structure = line;
    if (line.rfind("Verdict: ", 0) == 0) verdict = line;
    if (!std::regex_search(line, m, finding)) continue;
    ASSERT_LT(k, j["findings"].size()) << "more findings in the text than in the JSON";
    const json& f = j["findings"][k++];
    const std::string w = kind + " finding " + f["cause"].get<std::string>();
    EXPECT_EQ(m[1].str(), f["cause"].get<std::string>());
    std::size_t params = 0;
    for (auto it = std::sregex_iterator(line.begin(), line.end(), param); it != std::sregex_iterator(); ++it) {
      const std::string name = (*it)[1], v = (*it)[2], e = (*it)[3];
      ++params;
      const double value = json_param(f["parameters"], name);
      double error = json_param(f["uncertainty"], name);
      for (const char* other : {"uncertainty_jackknife", "uncertainty_corrected"})
        if (f.contains(other)) error = std::max(error, json_param(f[other], name));
      // The error to 2 significant digits, the value to the same place ("2270 ± 950": tens).
      const double unit = std::max(half_unit(e), 0.5 * std::pow(10.0, std::floor(std::log10(num(e))) - 1));
      EXPECT_LE(std::abs(num(v) - value), 1.02 * std::max(unit, half_unit(v))) << w << " " << name << ": text " << v << ", JSON " << value;
      EXPECT_LE(std::abs(num(e) - error), 1.02 * unit) << w << " " << name << " error: text " << e << ", JSON " << error;
    }
    EXPECT_GE(params, 1u) << w << ": no parameter read in " << line;
    ASSERT_TRUE(std::regex_search(line, m, mse)) << line;
    expect_sig(num(m[1]), f["heldout_mse_before"], 4, w + " held-out MSE before");
    expect_sig(num(m[2]), f["heldout_mse_after"], 4, w + " held-out MSE after");
    expect_dec(num(m[3]), f["delta_bic"], 1, w + " BIC change");
  }
  EXPECT_EQ(k, j["findings"].size()) << "findings in the JSON not in the text";
  if (k > 1) {
    ASSERT_FALSE(most.empty());
    EXPECT_EQ(most.rfind("Most of the gain: " + j["most_of_the_gain"].get<std::string>() + " ", 0), 0u) << most;
    for (const json& f : j["findings"]) {
      char want[160];
      std::snprintf(want, sizeof want, " %s %+.1f", f["cause"].get<std::string>().c_str(), f["removal_delta_bic"].get<double>());
      EXPECT_NE(most.find(want), std::string::npos) << most << " lacks" << want;
    }
  }
  ASSERT_FALSE(structure.empty());
  std::string want = "Residual structure left:";
  for (std::size_t i = 0; i < std::min<std::size_t>(4, j["residual_structure"].size()); ++i) {
    const json& r = j["residual_structure"][i];
    char part[160];
    std::snprintf(part, sizeof part, " %s %.3f%s", r["covariate"].get<std::string>().c_str(), r["score"].get<double>(),
                  r["significant"].get<bool>() ? " (significant)" : "");
    want += part;
  }
  EXPECT_EQ(structure.substr(0, want.size()), want);
  EXPECT_EQ(verdict.rfind("Verdict: " + j["verdict"].get<std::string>(), 0), 0u) << verdict;
}

INSTANTIATE_TEST_SUITE_P(Kinds, DiagnosisTextAndJson, ::testing::Values("proximity", "light", "ground", "camera", "drive"));

}  // namespace
}  // namespace test_text_and_json_cpp
