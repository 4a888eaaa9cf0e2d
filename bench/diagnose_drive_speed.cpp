// Speed of the diagnosis on a long drive log (issue: a 100,000-row drive log diagnosed against the
// whole catalogue in under 10 s on one core). Generates a seeded drive log of ROWS rows (default
// 100000; tests/diagnose_generators.hpp, ~10 Hz, runs to and fro before an obstacle) with the
// effect CAUSE hidden (default wheel_slip), diagnoses it (the engine is single-threaded: Ceres runs
// with one thread), and prints the wall and CPU time, the verdict and the machine.
// Usage: bench_diagnose_drive [ROWS] [CAUSE]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <string>
#include <thread>

#include "../tests/diagnose_generators.hpp"
#include "machine.hpp"
#include "epuck2/models/effects.hpp"

int main(int argc, char** argv) {
  using namespace epuck2;
  namespace gen = testing::diagnose;
  const int rows = argc > 1 ? std::stoi(argv[1]) : 100000;
  const std::string cause = argc > 2 ? argv[2] : models::effects::drive_catalogue()[models::effects::drive::wheel_slip].name;
  gen::Hidden h = gen::hidden(cause);
  const std::string text = gen::drive_log(20241121, h, rows);
  const auto log = logs::parse_log(text, "long_drive.csv", logs::Kind::drive);
  const auto wall0 = std::chrono::steady_clock::now();
  const std::clock_t cpu0 = std::clock();
  const auto report = diagnose::diagnose({log});
  const double cpu = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  std::printf("diagnose drive: %zu rows, %zu residuals, %zu effects considered; machine: %s\n", report.rows, report.residuals,
              report.effects_considered.size(), bench::machine().c_str());
  std::printf("wall %.2f s, CPU %.2f s (target: under 10 s on one core)\n", wall, cpu);
  std::printf("hidden %s", cause.c_str());
  for (const auto& [k, v] : h.truth) std::printf(" %s = %.4g", k.c_str(), v);
  std::printf("; verdict %s", report.verdict_name().c_str());
  for (const auto& f : report.findings) {
    std::printf("; %s:", f.cause.c_str());
    for (const auto& p : f.parameters) std::printf(" %s = %.4g +- %.2g", p.name.c_str(), p.value, p.std_error);
  }
  int heldout = 0, steps = 0;
  for (const auto& t : report.trials) {
    heldout += t.heldout_mse > 0;
    steps = std::max(steps, t.step);
  }
  std::printf("\nsearch: %d steps, %zu candidate fits, %d held-out evaluations (5 folds each)\n", steps, report.trials.size(), heldout);
  return 0;
}
