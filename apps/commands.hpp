// The subcommands of epuck2-fit, one file each (apps/cmd_*.cpp). Each setup function adds its
// subcommand to the app and arranges for its run function to be called after parsing.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

#include "epuck2/calibrate/no_usable_fit.hpp"
#include "epuck2/logs/log.hpp"

namespace epuck2::app {

/// What a subcommand's callback leaves for main to run after parsing.
using Action = std::function<int()>;

/// Bad usage that CLI11 cannot see (exit 2).
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
/// The data were read but no usable fit came out (exit 1): the libraries' own, so that a
/// calibration's writers (lib/calibrate) and the subcommands throw the same.
using NoUsableFit = calibrate::NoUsableFit;

void setup_battery(CLI::App& app, Action& action);
void setup_table5(CLI::App& app, Action& action);
void setup_codegen(CLI::App& app, Action& action);
void setup_simulate(CLI::App& app, Action& action);
/// `simulate KIND --like LOG` for the sensor kinds (cmd_simulate_like.cpp), under `simulate`.
void setup_simulate_like(CLI::App& sim, Action& action);
/// The options of `simulate KIND --like LOG`, every kind (battery's come from `simulate battery`).
struct LikeOptions {
  logs::Kind kind = logs::Kind::proximity;
  std::string like;
  std::string coefficients;  ///< a file; battery also `plugin` or `fitted`
  std::string battery_model;  ///< battery: the discharge model; empty: the file's (else cubic)
  std::string robot;         ///< --robot: the file's robot set asked for ("" : the log's robot's, if any)
  std::string robot_set;     ///< the robot set run (run_like's choice from `robot` and the log's robot)
  bool noise = false;
  std::uint64_t seed = 1;
  std::string output;
  bool skip_bad_rows = false;
};
/// Runs the model on the log's conditions and writes the simulated log (cmd_simulate_like.cpp).
int run_like(const LikeOptions& o);
void setup_generate(CLI::App& app, Action& action);
void setup_proximity(CLI::App& app, Action& action);
void setup_light(CLI::App& app, Action& action);
void setup_ground(CLI::App& app, Action& action);
void setup_camera(CLI::App& app, Action& action);
void setup_drive(CLI::App& app, Action& action);
void setup_nist(CLI::App& app, Action& action);
void setup_diagnose(CLI::App& app, Action& action);

}  // namespace epuck2::app
