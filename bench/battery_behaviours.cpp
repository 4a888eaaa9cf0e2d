// What the corrected behaviour changes, measured on the reference data. For each model, with the
// tables fitted to data/raw/battery:
//  * charge error: MSE against the reference logs when run over their own profiles (Table 5's
//    "simulated" column) in each behaviour;
//  * lifetime: the time at which the model empties, against the virtual robot's lifetime (noise
//    free, nominal robot) at the 16 table speeds and at 15 speeds between them (0.5, 1.5, ...),
//    where the plug-in's interpolation quirk acts;
//  * the first tick from a full charge.
//   build/bin/battery_behaviours
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "epuck2/calibrate/battery.hpp"
#include "epuck2/models/battery_simulation.hpp"
#include "epuck2/virtual_robot/battery.hpp"
#include "machine.hpp"

namespace mb = epuck2::models::battery;
namespace vr = epuck2::virtual_robot::battery;
namespace fs = std::filesystem;

namespace {
double model_lifetime(mb::Model m, mb::Behaviour b, const mb::Tables& t, double speed) {
  const auto s = mb::simulate_discharge(m, b, t, {{0.0, speed}, {60000.0, speed}}, 0.1, 1.0);
  return s.back().charge <= 0 ? s.back().time_s : std::numeric_limits<double>::infinity();
}
}  // namespace

int main() {
  std::vector<std::string> paths;
  for (const auto& e : fs::directory_iterator(fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / "battery"))
    if (e.path().extension() == ".csv") paths.push_back(e.path().string());
  std::sort(paths.begin(), paths.end());
  const auto runs = epuck2::calibrate::battery_runs(epuck2::logs::read_logs(paths, epuck2::logs::Kind::battery));
  const auto fit = epuck2::calibrate::fit_battery(runs);
  if (!fit.tables) {
    std::fprintf(stderr, "the reference logs do not cover 0..15 cm/s\n");
    return 1;
  }
  const mb::Tables& t = *fit.tables;
  std::printf("battery_behaviours: plug-in compatible vs corrected, tables fitted to %zu reference logs\n", runs.size());
  std::printf("machine: %s\n\n", epuck2::bench::machine().c_str());

  const auto argos_mse = epuck2::calibrate::simulated_mse(runs, t, mb::Behaviour::argos_compatible);
  const auto corr_mse = epuck2::calibrate::simulated_mse(runs, t, mb::Behaviour::corrected);

  // Lifetime truth: the nominal virtual robot, noise free.
  vr::SimulationOptions clean;
  clean.noise = false;
  std::printf("%-13s %12s %12s | %28s | %28s | %18s\n", "model", "MSE argos", "MSE corr.",
              "lifetime error, table speeds", "lifetime error, in between", "first tick at 7 cm/s");
  std::printf("%-13s %12s %12s | %13s %14s | %13s %14s | %8s %9s\n", "", "", "", "argos", "corrected", "argos",
              "corrected", "argos", "corr.");
  for (mb::Model m : mb::kAllModels) {
    double err_a = 0, err_c = 0, err_ha = 0, err_hc = 0;
    int n = 0, nh = 0;
    for (int i = 0; i <= 30; ++i) {
      const double speed = 0.5 * i;
      const double truth = vr::simulate_protocol(speed, vr::RobotParameters{}, 1, clean).stop_time_s;
      const double la = model_lifetime(m, mb::Behaviour::argos_compatible, t, speed);
      const double lc = model_lifetime(m, mb::Behaviour::corrected, t, speed);
      const double ea = std::abs(la - truth) / truth, ec = std::abs(lc - truth) / truth;
      if (i % 2 == 0) {
        err_a += ea;
        err_c += ec;
        ++n;
      } else {
        err_ha += ea;
        err_hc += ec;
        ++nh;
      }
    }
    // First tick from a full charge at 7 cm/s (0.007 m in 0.1 s).
    const double drop_a = 1.0 - mb::step(m, mb::Behaviour::argos_compatible, t, 1.0, 0.007, 0.1);
    const double drop_c = 1.0 - mb::step(m, mb::Behaviour::corrected, t, 1.0, 0.007, 0.1);
    std::printf("%-13s %12.5f %12.5f | %12.2f%% %13.2f%% | %12.2f%% %13.2f%% | %8.2e %9.2e\n",
                std::string(mb::to_string(m)).c_str(), argos_mse.get(m), corr_mse.get(m), 100 * err_a / n,
                100 * err_c / n, 100 * err_ha / nh, 100 * err_hc / nh, drop_a, drop_c);
  }
  std::printf("\nfirst tick: the drop from a full charge in one 0.1 s tick at 7 cm/s\n");
  std::printf("lifetime error: mean |model lifetime - virtual robot lifetime| / virtual robot lifetime\n");
  return 0;
}
