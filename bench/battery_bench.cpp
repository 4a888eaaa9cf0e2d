// Battery benchmarks (Google Benchmark): the time to fit the whole reference set
// (data/raw/battery, 32 logs), and nanoseconds per discharge step for each model in both
// behaviours. Targets (issue): the whole set under 1 s; a Cubic step under 50 ns.
//   build/bin/bench_battery [--benchmark_min_time=0.5]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "epuck2/calibrate/battery.hpp"
#include "epuck2/fit/solver_log.hpp"
#include "heap.hpp"  // apps/heap.hpp: the programs' heap setting
#include "epuck2/models/plugin_battery_tables.hpp"
#include "machine.hpp"

namespace mb = epuck2::models::battery;
namespace fs = std::filesystem;

namespace {

std::vector<epuck2::calibrate::BatteryRun> reference_runs() {
  std::vector<std::string> paths;
  for (const auto& e : fs::directory_iterator(fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / "battery"))
    if (e.path().extension() == ".csv") paths.push_back(e.path().string());
  std::sort(paths.begin(), paths.end());
  return epuck2::calibrate::battery_runs(epuck2::logs::read_logs(paths, epuck2::logs::Kind::battery));
}

// The whole reference set: robust (the default: wild readings beyond 6 robust sd left out) and
// plain least squares (--least-squares), so the robust rule's cost is measured in one run.
void BM_FitReferenceSet(benchmark::State& state, double reject_sd) {
  const auto runs = reference_runs();
  std::size_t rows = 0;
  for (const auto& r : runs) rows += r.time_s.size();
  for (auto _ : state) {
    auto fit = epuck2::calibrate::fit_battery(runs, {}, reject_sd);
    benchmark::DoNotOptimize(fit);
  }
  state.counters["logs"] = static_cast<double>(runs.size());
  state.counters["rows"] = static_cast<double>(rows);
}
BENCHMARK_CAPTURE(BM_FitReferenceSet, robust, epuck2::calibrate::kBatteryRejectSd)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(BM_FitReferenceSet, least_squares, 0.0)->Unit(benchmark::kMillisecond)->MinTime(2.0);

// One tick from charge 0.95 down (restarting at 0.95 when empty), at 6.37 cm/s (between two
// speed tables: the interpolating path, two table evaluations) or at 7.00 cm/s (one table).
void BM_Step(benchmark::State& state, mb::Model model, mb::Behaviour behaviour, double speed_m_s = 0.0637) {
  const mb::Tables& t = mb::plugin_tables();
  const double dt = 0.1;
  const double dpos = speed_m_s * dt;
  double charge = 0.95;
  for (auto _ : state) {
    charge = mb::step(model, behaviour, t, charge, dpos, dt);
    if (charge <= 0.01) charge = 0.95;
    benchmark::DoNotOptimize(charge);
  }
}
BENCHMARK_CAPTURE(BM_Step, simple_argos, mb::Model::simple, mb::Behaviour::argos_compatible);
BENCHMARK_CAPTURE(BM_Step, linear_argos, mb::Model::linear, mb::Behaviour::argos_compatible);
BENCHMARK_CAPTURE(BM_Step, cubic_argos, mb::Model::cubic, mb::Behaviour::argos_compatible);
BENCHMARK_CAPTURE(BM_Step, approximated_argos, mb::Model::approximated, mb::Behaviour::argos_compatible);
BENCHMARK_CAPTURE(BM_Step, simple_corrected, mb::Model::simple, mb::Behaviour::corrected);
BENCHMARK_CAPTURE(BM_Step, linear_corrected, mb::Model::linear, mb::Behaviour::corrected);
BENCHMARK_CAPTURE(BM_Step, cubic_corrected, mb::Model::cubic, mb::Behaviour::corrected);
BENCHMARK_CAPTURE(BM_Step, approximated_corrected, mb::Model::approximated, mb::Behaviour::corrected);
BENCHMARK_CAPTURE(BM_Step, cubic_argos_at_table_speed, mb::Model::cubic, mb::Behaviour::argos_compatible, 0.07);
BENCHMARK_CAPTURE(BM_Step, cubic_corrected_at_table_speed, mb::Model::cubic, mb::Behaviour::corrected, 0.07);

// The same ticks as simulate_discharge runs them: the corrected Cubic's root searches carried
// from tick to tick (corrected::CubicHints; the plug-in arithmetic has no state). The hints are
// not reset when the charge restarts at 0.95, as a battery never jumps back up.
void BM_StepCarried(benchmark::State& state, mb::Model model, mb::Behaviour behaviour, double speed_m_s = 0.0637) {
  const mb::Tables& t = mb::plugin_tables();
  const double dt = 0.1;
  const double dpos = speed_m_s * dt;
  double charge = 0.95;
  mb::corrected::CubicHints hints;
  for (auto _ : state) {
    charge = mb::step(model, behaviour, t, charge, dpos, dt, hints);
    if (charge <= 0.01) charge = 0.95;
    benchmark::DoNotOptimize(charge);
  }
}
BENCHMARK_CAPTURE(BM_StepCarried, cubic_corrected, mb::Model::cubic, mb::Behaviour::corrected);
BENCHMARK_CAPTURE(BM_StepCarried, cubic_corrected_at_table_speed, mb::Model::cubic, mb::Behaviour::corrected, 0.07);

// The floor under the plug-in's Cubic step: a chain of glibc cbrt calls (each argument waits on
// the last result, as each tick's Cardano root waits on the last tick's charge).
void BM_CbrtChain(benchmark::State& state) {
  double x = 0.95;
  for (auto _ : state) {
    x = std::cbrt(x + 0.3);
    benchmark::DoNotOptimize(x);
  }
}
BENCHMARK(BM_CbrtChain);

// A swarm as the simulator steps it: every robot's battery once per tick, 50 robots as in the
// paper's execution-time experiments (Fig. 13), each with its own charge and speed (robot r at
// r mod 16 cm/s, plus 0.37 cm/s for odd r: half on a speed table, half between two). One
// robot's tick does not wait on another's, so the processor overlaps them: this is the cost per
// robot per tick that a swarm simulation pays, where BM_Step above is the latency of one robot's
// chain of ticks (each waiting on the last: the plug-in's Cardano root, glibc's cbrt included).
void BM_SwarmStep(benchmark::State& state, mb::Model model, mb::Behaviour behaviour) {
  constexpr int kRobots = 50;
  const mb::Tables& t = mb::plugin_tables();
  const double dt = 0.1;
  std::vector<double> charge(kRobots), dpos(kRobots);
  std::vector<mb::corrected::CubicHints> hints(kRobots);
  for (int r = 0; r < kRobots; ++r) {
    charge[static_cast<std::size_t>(r)] = 0.95 - 0.005 * r;
    dpos[static_cast<std::size_t>(r)] = (0.01 * (r % 16) + (r % 2 ? 0.0037 : 0.0)) * dt;
  }
  for (auto _ : state) {
    for (std::size_t r = 0; r < kRobots; ++r) {
      double c = mb::step(model, behaviour, t, charge[r], dpos[r], dt, hints[r]);
      if (c <= 0.01) c = 0.95;
      charge[r] = c;
    }
    benchmark::DoNotOptimize(charge.data());
    benchmark::ClobberMemory();
  }
  // Seconds per robot-step (printed with its SI prefix, e.g. "52.1ns").
  state.counters["per_robot_step"] = benchmark::Counter(static_cast<double>(state.iterations()) * kRobots,
                                                        benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK_CAPTURE(BM_SwarmStep, cubic_argos, mb::Model::cubic, mb::Behaviour::argos_compatible);
BENCHMARK_CAPTURE(BM_SwarmStep, cubic_corrected, mb::Model::cubic, mb::Behaviour::corrected);
BENCHMARK_CAPTURE(BM_SwarmStep, linear_argos, mb::Model::linear, mb::Behaviour::argos_compatible);
BENCHMARK_CAPTURE(BM_SwarmStep, approximated_argos, mb::Model::approximated, mb::Behaviour::argos_compatible);

}  // namespace

int main(int argc, char** argv) {
  epuck2::fit::silence_solver_log();       // the solver's chatter
  epuck2::app::keep_freed_heap();          // as epuck2-fit runs its fits
  benchmark::AddCustomContext("machine", epuck2::bench::machine());
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
