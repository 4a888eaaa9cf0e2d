// The sensor subcommands (proximity, light, ground, camera, drive) run as the real binary
// (EPUCK2_FIT_EXE): success on the shipped logs with the JSON shape the codegen reads, and exit 2
// with file:line:column on bad input, leaving an existing -o file untouched.
#include <gtest/gtest.h>

#include "cli_harness.hpp"
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using SensorCli = epuck2::testing::CliTest;
using epuck2::testing::CliRun;
using epuck2::testing::slurp;

struct CliCase {
  std::string kind;
  std::vector<std::string> parameters;  ///< keys that must be in "parameters" and "std_errors"
  std::string header;                   ///< a valid header for this kind
  std::string good_row;
  std::string metadata;                 ///< required metadata lines
};

const std::vector<CliCase> kCases{
    {"proximity", {"a", "b", "c", "mean_a", "mean_b", "mean_c"}, "distance_m,sensor,value", "0.02,0,1971", ""},
    {"light", {"gamma"}, "distance_m,intensity,sensor,value", "0.2,1,0,3519", ""},
    {"ground", {"gain", "offset"}, "grey,sensor,value", "0.5,1,512", ""},
    {"camera", {"fov_deg", "cx_px", "cy_px"}, "forward_m,lateral_m,vertical_m,px,py", "0.5,0.05,0,65,60", ""},
    {"drive", {"steps_per_m", "tof_offset_mm", "tof_scale"},
     "time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm", "0,5,5,0,0,300", "# obstacle_distance_m: 0.3\n"},
};

}  // namespace

TEST_F(SensorCli, EachSubcommandFitsTheShippedLogs) {
  for (const CliCase& c : kCases) {
    const fs::path json_out = dir_ / (c.kind + ".json");
    const CliRun r = run(c.kind + shipped(c.kind) + " --json -o \"" + json_out.string() + "\"");
    ASSERT_EQ(r.exit_code, 0) << c.kind << ": " << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j.at("kind"), c.kind);
    for (const auto& p : c.parameters) {
      EXPECT_TRUE(j.at("parameters").contains(p)) << c.kind << " " << p;
      EXPECT_TRUE(j.at("std_errors").contains(p)) << c.kind << " " << p;
    }
    EXPECT_TRUE(j.at("mse").is_number());
    EXPECT_GT(j.at("observations").get<int>(), 0);
    EXPECT_FALSE(j.at("sources").empty());
    EXPECT_EQ(nlohmann::json::parse(slurp(json_out)), j) << "-o writes what --json prints";
    // The human report is the default.
    const CliRun h = run(c.kind + shipped(c.kind));
    EXPECT_EQ(h.exit_code, 0);
    EXPECT_FALSE(h.out.empty());
    EXPECT_FALSE(nlohmann::json::accept(h.out));
  }
  // Ground's parameters are arrays of 3, one per sensor.
  const CliRun g = run("ground" + shipped("ground") + " --json");
  const auto j = nlohmann::json::parse(g.out);
  EXPECT_EQ(j.at("parameters").at("gain").size(), 3u);
  EXPECT_EQ(j.at("std_errors").at("offset").size(), 3u);
}

// Every coefficient file holds the reading noise of each of its channels (docs/coefficient-files.md):
// sd in the reading's units, per sensor where the kind has several, where it comes from, and the
// plug-in's uniform level of the same variance, sqrt(3) sd / scale, with the plug-in's scales
// (its source: x 4095 for proximity and light, x 1023 ground, x 2000 mm ToF, x 32767 encoders).
TEST_F(SensorCli, EveryFileHasTheReadingNoiseOfItsChannels) {
  struct Channel {
    std::string kind, channel, unit, from;
    std::size_t sensors;  ///< per_sensor_sd entries, 0: none
    double scale;         ///< 0: no plug-in noise (camera)
  };
  const std::vector<Channel> channels{{"proximity", "proximity", "counts", "replicates", 8, 4095},
                                      {"light", "light", "counts", "replicates", 8, 4095},
                                      {"ground", "ground", "counts", "replicates", 3, 1023},
                                      {"camera", "camera", "px", "replicates", 0, 0},
                                      {"drive", "tof", "mm", "replicates", 0, 2000},
                                      {"drive", "encoder", "steps", "residuals", 0, 32767}};
  for (const Channel& c : channels) {
    SCOPED_TRACE(c.kind + " " + c.channel);
    const CliRun r = run(c.kind + shipped(c.kind) + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("noise"));
    const nlohmann::json& n = j.at("noise").at(c.channel);
    EXPECT_EQ(n.at("unit"), c.unit);
    EXPECT_EQ(n.at("from"), c.from);
    const double sd = n.at("sd").get<double>();
    EXPECT_GT(sd, 0.0);
    EXPECT_GT(n.at("n").get<int>(), 100);
    if (c.sensors) {
      ASSERT_EQ(n.at("per_sensor_sd").size(), c.sensors);
      ASSERT_EQ(n.at("per_sensor_n").size(), c.sensors);
    } else {
      EXPECT_FALSE(n.contains("per_sensor_sd"));
    }
    if (c.scale > 0)
      EXPECT_NEAR(n.at("argos_uniform_level").get<double>(), std::sqrt(3.0) * sd / c.scale, 1e-12 * sd);
    else
      EXPECT_FALSE(n.contains("argos_uniform_level"));
    // The human report says it too.
    const CliRun h = run(c.kind + shipped(c.kind));
    EXPECT_NE(h.out.find("Reading noise (" + c.channel + "): sd "), std::string::npos) << h.out;
  }
  // Several robots: each robot's own noise beside the pooled one.
  const auto g = nlohmann::json::parse(run("ground" + shipped("ground") + " --json").out);
  for (const auto& [robot, set] : g.at("robots").items()) EXPECT_EQ(set.at("noise").at("ground").at("unit"), "counts") << robot;
}

TEST_F(SensorCli, BadInputExitsTwoWithFileLineColumnAndLeavesOutputAlone) {
  for (const CliCase& c : kCases) {
    const std::string previous = "{\"previous\": true}\n";
    const std::string out = write(c.kind + "_previous.json", previous);
    const std::string rows = c.metadata + c.header + "\n" + c.good_row + "\n";
    // Drop the header's last column: a missing required column (line 1 or 2 of the file).
    const std::string missing_header = c.header.substr(0, c.header.rfind(','));
    const std::string bad_row_nonnumeric = c.good_row.substr(0, c.good_row.rfind(',')) + ",abc";
    const std::string bad_row_nan = c.good_row.substr(0, c.good_row.rfind(',')) + ",nan";
    const int header_line = c.metadata.empty() ? 1 : 2;
    struct Bad {
      std::string name, text, expect;
    };
    const std::vector<Bad> bads{
        {"missing.csv", c.metadata + missing_header + "\n" + c.good_row.substr(0, c.good_row.rfind(',')) + "\n",
         "missing.csv:" + std::to_string(header_line) + ":"},
        {"nonnumeric.csv", rows + bad_row_nonnumeric + "\n", "nonnumeric.csv:" + std::to_string(header_line + 2) + ":"},
        {"nan.csv", rows + bad_row_nan + "\n", "nan.csv:" + std::to_string(header_line + 2) + ":"},
    };
    for (const Bad& b : bads) {
      const std::string path = write(c.kind + "_" + b.name, b.text);
      const CliRun r = run(c.kind + " \"" + path + "\" -o \"" + out + "\"");
      EXPECT_EQ(r.exit_code, 2) << c.kind << " " << b.name << ": " << r.err;
      EXPECT_NE(r.err.find(c.kind + "_" + b.expect), std::string::npos) << c.kind << " " << b.name << ": " << r.err;
      EXPECT_EQ(slurp(out), previous) << c.kind << " " << b.name << ": -o replaced";
    }
    const CliRun u = run(c.kind + shipped(c.kind) + " --no-such-option -o \"" + out + "\"");
    EXPECT_EQ(u.exit_code, 2) << c.kind;
    EXPECT_EQ(slurp(out), previous);
    const CliRun none = run(c.kind + " \"" + (dir_ / "does-not-exist.csv").string() + "\"");
    EXPECT_EQ(none.exit_code, 2) << c.kind;
  }
}

TEST_F(SensorCli, TooLittleDataIsNoUsableFit) {
  // One reading per kind: the data are read but no fit can come out (exit 1), nothing written.
  for (const CliCase& c : kCases) {
    const std::string path = write(c.kind + "_one.csv", c.metadata + c.header + "\n" + c.good_row + "\n");
    const fs::path out = dir_ / (c.kind + "_one.json");
    const CliRun r = run(c.kind + " \"" + path + "\" -o \"" + out.string() + "\"");
    EXPECT_EQ(r.exit_code, 1) << c.kind << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.kind;
  }
}
