// The noise a diagnosis writes into its extended model is the noise of one reading (issue #20,
// item 2): the replicates' where the logs repeat readings, never the misfit a model leaves; and the
// CLI warns when the final model's residuals are implausible next to the replicates.
// The log is drawn here (std::mt19937_64, its own curve and clamps): its noise sd, 10 counts, is
// the generator's truth.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/diagnose/extended_model.hpp"
#include "epuck2/diagnose/reading_noise.hpp"
#include "epuck2/logs/log.hpp"

// This file's `using namespace` stays in its own named namespace, so it opens nothing to the
// files compiled after it in the same unity unit (tests/CMakeLists.txt).
namespace test_diagnose_noise_cpp {
namespace {

using namespace epuck2;

constexpr double kNoiseCounts = 10.0;

/// A proximity curve Eq. 1 cannot follow (3800 e^(-d / 12 mm)), 8 sensors, 20 readings at each of
/// 13 distances, N(0, 10 counts).
logs::Log misfit_proximity(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, kNoiseCounts);
  std::ostringstream csv;
  csv << "distance_m,sensor,value\n";
  for (int rep = 0; rep < 20; ++rep)
    for (int k = 0; k <= 12; ++k)
      for (int sensor = 0; sensor < 8; ++sensor) {
        const double d = 0.005 * k;
        const double v = std::round(std::min(4095.0, std::max(0.0, 3800.0 * std::exp(-d / 0.012) + noise(rng))));
        csv << d << "," << sensor << "," << v << "\n";
      }
  return logs::parse_log(csv.str(), "misfit.csv", logs::Kind::proximity);
}

TEST(DiagnoseNoise, TheModelsNoiseIsTheReplicatesNotTheMisfit) {
  const std::vector<logs::Log> logs{misfit_proximity(5)};
  diagnose::Options o;
  o.effects = {"ambient_offset"};  // cannot bend Eq. 1 into an exponential: misfit stays
  const diagnose::ModelInputs inputs = diagnose::model_inputs(logs, o);
  const diagnose::Report r = diagnose::diagnose(logs, o);
  ASSERT_TRUE(r.supported) << r.message;
  ASSERT_GT(r.noise_sd, 3 * kNoiseCounts) << "the test needs a model that misfits";
  ASSERT_EQ(inputs.replicate_noise.count("proximity"), 1u);
  EXPECT_EQ(inputs.replicate_noise.at("proximity").from, "replicates");
  const auto m = diagnose::extended_proximity(r, nullptr, inputs);
  for (double sd : m.noise_sd_raw) EXPECT_NEAR(sd, kNoiseCounts, 0.1 * kNoiseCounts);
  // The CLI's warning names both numbers.
  const auto w = diagnose::noise_warnings(r, inputs.replicate_noise);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("not reading noise"), std::string::npos) << w[0];
  // The file says the same (what ARGoS and simulate --like draw).
  const auto j = diagnose::extended_model_json(r, inputs);
  EXPECT_NEAR(j.at("noise").at("proximity").at("sd").get<double>(), kNoiseCounts, 0.1 * kNoiseCounts) << j.at("noise").dump();
}

// Without replicates (no two readings under the same conditions) the final model's residuals.
TEST(DiagnoseNoise, WithoutReplicatesTheFinalResiduals) {
  std::map<std::string, calibrate::ReadingNoise> none;
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(none, "proximity", 7.0), std::sqrt(49.0 - 1.0 / 12.0));
  calibrate::ReadingNoise n;
  n.channel = "proximity";
  n.sd = 9.7;
  n.from = "replicates";
  n.n = 100;
  n.per_sensor_sd = {8.0, 12.0};
  n.per_sensor_n = {50, 0};
  const std::map<std::string, calibrate::ReadingNoise> rep{{"proximity", n}};
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(rep, "proximity", 211.0), std::sqrt(9.7 * 9.7 - 1.0 / 12.0));
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(rep, "proximity", 211.0, 0), std::sqrt(64.0 - 1.0 / 12.0));
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(rep, "proximity", 211.0, 1), std::sqrt(9.7 * 9.7 - 1.0 / 12.0));  // no readings of its own
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(rep, "proximity", 211.0, 0, false), 8.0);
  // "Replicates" scattering more than the final residuals were not under the same conditions (an
  // angle or a temperature varying within a group): the residuals bound the noise.
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(rep, "proximity", 5.0, -1, false), 5.0);
  EXPECT_DOUBLE_EQ(diagnose::model_noise_sd(rep, "proximity", 5.0, 1, false), 5.0);
}

}  // namespace
}  // namespace test_diagnose_noise_cpp
