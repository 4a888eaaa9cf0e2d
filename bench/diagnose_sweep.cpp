// The diagnosis sweep: for every supported kind and every hidden effect of
// tests/diagnose_generators.hpp, SEEDS seeded logs (default 40); prints the rate of right
// verdicts, of parameters within 10 % (where the effect has parameters), the wall time, and the
// machine. Usage: bench_diagnose_sweep [SEEDS] [KIND...]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "../tests/diagnose_generators.hpp"
#include "machine.hpp"


int main(int argc, char** argv) {
  using namespace epuck2;
  namespace gen = testing::diagnose;
  const int seeds = argc > 1 ? std::stoi(argv[1]) : 40;
  std::vector<logs::Kind> kinds{logs::Kind::ground, logs::Kind::proximity, logs::Kind::light,
                                logs::Kind::camera, logs::Kind::drive,     logs::Kind::battery};
  if (argc > 2) {
    kinds.clear();
    for (int a = 2; a < argc; ++a)
      if (auto k = logs::parse_kind(argv[a])) kinds.push_back(*k);
  }
  std::printf("diagnose sweep: %d seeds per kind and effect; machine: %s\n", seeds, bench::machine().c_str());
  std::printf("params: parameters within 10 %% of the truth, over the logs whose verdict is right and whose effect is large\n"
              "enough to matter (tests/diagnose_generators.hpp: Hidden::parameters_matter)\n");
  std::printf("%-10s %-26s %8s %16s %10s %9s  %s\n", "kind", "hidden effect", "verdict", "params", "mean rows", "s/log", "wrong verdicts seen");
  for (logs::Kind kind : kinds) {
    for (const std::string& cause : gen::hidden_effects(kind)) {
      int right = 0, checked = 0, params_right = 0;
      double rows = 0, seconds = 0;
      std::map<std::string, int> wrong;
      for (int s = 0; s < seeds; ++s) {
        gen::Hidden h = gen::hidden(cause);
        const std::uint64_t seed = 1000003ULL * static_cast<std::uint64_t>(s + 1) + std::hash<std::string>{}(cause) % 1000;
        const std::string text = gen::make_log(kind, seed, h);
        const auto log = logs::parse_log(text, "sweep.csv", kind);
        rows += static_cast<double>(log.rows());
        const auto t0 = std::chrono::steady_clock::now();
        const auto report = diagnose::diagnose({log});
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const gen::Outcome o = gen::judge(h, report);
        right += o.verdict_right;
        if (!o.verdict_right && std::getenv("DIAGNOSE_SWEEP_DUMP")) {
          // Keep the failing log for a look with `epuck2-fit diagnose`.
          std::ofstream(std::string(std::getenv("DIAGNOSE_SWEEP_DUMP")) + "/" + std::string(logs::to_string(kind)) + "_" +
                        cause.substr(0, cause.find(':')) + "_" + std::to_string(s) + ".csv")
              << text;
        }
        if (!o.verdict_right) ++wrong[o.verdict + (o.verdict == "unexplained" ? "(" + o.first_covariate + ")" : "")];
        if (o.parameters_checked) {
          ++checked;
          params_right += o.parameters_right;
        }
      }
      std::string w;
      for (const auto& [v, c] : wrong) w += v + " x" + std::to_string(c) + " ";
      char params[32] = "-";
      if (checked) std::snprintf(params, sizeof params, "%5.1f %% of %d", 100.0 * params_right / checked, checked);
      std::printf("%-10s %-26s %6.1f %% %16s %10.0f %9.3f  %s\n", std::string(logs::to_string(kind)).c_str(), cause.c_str(),
                  100.0 * right / seeds, params, rows / seeds, seconds / seeds, w.c_str());
      std::fflush(stdout);
    }
  }
  return 0;
}
