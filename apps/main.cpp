// epuck2-fit: the command line. Exit status: 0 success; 1 data read but no usable fit; 2 bad
// usage or bad input (the message names file, line and column).
#include <glog/logging.h>

#include <iostream>

#include "commands.hpp"
#include "heap.hpp"
#include "epuck2/logs/log.hpp"

#ifndef EPUCK2_VERSION
#define EPUCK2_VERSION "unknown"
#endif

int main(int argc, char** argv) {
  using namespace epuck2::app;
  // Ceres reports through glog; its messages are not for our users (fits report their own status).
  FLAGS_minloglevel = google::GLOG_FATAL;
  google::InitGoogleLogging(argv[0]);
  // Battery and diagnosis runs fit hundreds of times: freed memory waits for the next fit.
  epuck2::app::keep_freed_heap();
  CLI::App app{"epuck2-fit: calibrate and diagnose E-Puck2 simulation models from raw robot logs"};
  app.set_version_flag("--version", std::string("epuck2-fit ") + EPUCK2_VERSION);
  app.require_subcommand(1);
  Action action;
  setup_battery(app, action);
  setup_table5(app, action);
  setup_codegen(app, action);
  setup_simulate(app, action);
  setup_generate(app, action);
  setup_proximity(app, action);
  setup_light(app, action);
  setup_ground(app, action);
  setup_camera(app, action);
  setup_drive(app, action);
  setup_nist(app, action);
  setup_diagnose(app, action);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help/version or the parse error
    return code == 0 ? 0 : 2;
  }
  if (!action) return 0;
  try {
    return action();
  } catch (const epuck2::logs::InputError& e) {
    std::cerr << "error: " << e.what() << '\n';
    return 2;
  } catch (const UsageError& e) {
    // Messages may quote input (robot names, JSON keys): control characters are escaped.
    std::cerr << "error: " << epuck2::logs::escape_control(e.what()) << '\n';
    return 2;
  } catch (const NoUsableFit& e) {
    std::cerr << "error: no usable fit: " << epuck2::logs::escape_control(e.what()) << '\n';
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "error: " << epuck2::logs::escape_control(e.what()) << '\n';
    return 2;
  }
}
