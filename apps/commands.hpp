// The subcommands of epuck2-fit, one file each (apps/cmd_*.cpp). Each setup function adds its
// subcommand to the app and arranges for its run function to be called after parsing.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <stdexcept>
#include <string>

namespace epuck2::app {

/// What a subcommand's callback leaves for main to run after parsing.
using Action = std::function<int()>;

/// Bad usage that CLI11 cannot see (exit 2).
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
/// The data were read but no usable fit came out (exit 1).
struct NoUsableFit : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void setup_battery(CLI::App& app, Action& action);
void setup_table5(CLI::App& app, Action& action);
void setup_codegen(CLI::App& app, Action& action);
void setup_simulate(CLI::App& app, Action& action);
/// `simulate KIND --like LOG` for the sensor kinds (cmd_simulate_like.cpp), under `simulate`.
void setup_simulate_like(CLI::App& sim, Action& action);
void setup_generate(CLI::App& app, Action& action);
void setup_proximity(CLI::App& app, Action& action);
void setup_light(CLI::App& app, Action& action);
void setup_ground(CLI::App& app, Action& action);
void setup_camera(CLI::App& app, Action& action);
void setup_drive(CLI::App& app, Action& action);
void setup_nist(CLI::App& app, Action& action);
void setup_diagnose(CLI::App& app, Action& action);

}  // namespace epuck2::app
