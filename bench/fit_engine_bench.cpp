// bench_fit_engine: the fitting engine's coefficients and wall times, as JSON on stdout, for the
// side-by-side with scipy and lmfit (bench/side_by_side.py).
//
//   bench_fit_engine --nist DIR --battery DIR [--min-seconds S] [--default-heap]
//
// The program calls epuck2::app::keep_freed_heap() first, as epuck2-fit does (--default-heap: glibc's
// own trimming, under which each fit faults its pages in again).
//
// (a) every NIST StRD problem from start 1, fitted with the NIST options (multi-strategy search
//     and extended-precision polish: what meets the certified digits) and, separately timed, with
//     one plain Levenberg-Marquardt solve at the same tolerances (the like-for-like with one
//     MINPACK call);
// (b) the battery reference set: per speed, a least-squares cubic charge = a u^3 + b u^2 + c u + d
//     in scaled time u = time_s / 3600 (hours; the same scaling in every tool) on the pooled logs
//     robot-X_speed-SS.csv, from the start (a, b, c, d) = (0, 0, 0, 1), with the default
//     FitOptions (what other callers of fit_curve get: the cubic declares itself linear in its
//     parameters, so the fit starts from the linear least-squares solution and Ceres confirms
//     it; covariance and standard errors computed), and again without the linear start
//     (Levenberg-Marquardt from the start, as for a nonlinear model), with one residual block and
//     with one block per observation.
// Each fit is repeated until --min-seconds have passed (at least 5 times); the median is reported.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "heap.hpp"  // apps/heap.hpp: the programs' heap setting
#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/solver_log.hpp"
#include "epuck2/nist/nist.hpp"
#include "epuck2/logs/log.hpp"

namespace {

using namespace epuck2;

/// Seconds per hour: the battery cubic's time unit (u = time_s / kHourS).
constexpr double kHourS = 3600.0;
constexpr int kMinRepeats = 5;

/// charge = a u^3 + b u^2 + c u + d, u in hours.
struct Cubic {
  static constexpr int kParameters = 4;
  static constexpr bool kLinearInParameters = true;  // fit_curve starts from linear least squares
  template <typename T>
  T operator()(const T* p, double u) const {
    return ((p[0] * u + p[1]) * u + p[2]) * u + p[3];
  }
};

template <class F>
double median_seconds(F&& f, double min_seconds) {
  std::vector<double> times;
  const auto begin = std::chrono::steady_clock::now();
  while (static_cast<int>(times.size()) < kMinRepeats ||
         std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count() < min_seconds) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

int usage() {
  std::cerr << "usage: bench_fit_engine --nist DIR --battery DIR [--min-seconds S] [--default-heap]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string nist_dir, battery_dir;
  double min_seconds = 0.2;
  bool default_heap = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--default-heap") {
      default_heap = true;
      continue;
    }
    if (i + 1 >= argc) return usage();
    if (a == "--nist") nist_dir = argv[++i];
    else if (a == "--battery") battery_dir = argv[++i];
    else if (a == "--min-seconds") min_seconds = std::stod(argv[++i]);
    else return usage();
  }
  if (nist_dir.empty() && battery_dir.empty()) return usage();
  if (!default_heap) epuck2::app::keep_freed_heap();
  epuck2::fit::silence_solver_log();  // the solver's step-by-step complaints are not the report
  try {
    nlohmann::json out;
    out["machine"] = {{"cpu", cpu_model()}, {"hardware_threads", std::thread::hardware_concurrency()}};
    out["min_seconds_per_fit"] = min_seconds;
    out["heap"] = default_heap ? "glibc defaults" : "keep_freed_heap (heap.hpp)";

    if (!nist_dir.empty()) {
      fit::FitOptions single = nist::default_options();
      single.restarts = 0;
      single.try_alternatives = false;
      nlohmann::json runs = nlohmann::json::array();
      for (const auto& name : nist::problem_names()) {
        const nist::Problem p = nist::read(nist_dir + "/" + name + ".dat");
        const fit::FitResult f = nist::fit(p, 1);
        const fit::FitResult g = nist::fit(p, 1, single);
        const double t = median_seconds([&] { nist::fit(p, 1); }, min_seconds);
        const double t_single = median_seconds([&] { nist::fit(p, 1, single); }, min_seconds);
        std::vector<double> start;
        for (const auto& c : p.parameters) start.push_back(c.start1);
        runs.push_back({{"problem", name},
                        {"start", 1},
                        {"start_values", start},
                        {"values", f.values()},
                        {"usable", f.usable},
                        {"seconds", t},
                        {"values_single_solve", g.values()},
                        {"seconds_single_solve", t_single}});
      }
      out["nist"] = runs;
    }

    if (!battery_dir.empty()) {
      namespace fs = std::filesystem;
      const std::regex name_re(R"(robot-([A-Za-z0-9]+)_speed-([0-9]+)\.csv)");
      std::map<int, std::vector<fs::path>> by_speed;
      for (const auto& e : fs::directory_iterator(battery_dir)) {
        std::smatch m;
        const std::string fname = e.path().filename().string();
        if (e.is_regular_file() && std::regex_match(fname, m, name_re)) by_speed[std::stoi(m[2])].push_back(e.path());
      }
      nlohmann::json sets = nlohmann::json::array();
      for (auto& [speed, files] : by_speed) {
        std::sort(files.begin(), files.end());
        std::vector<double> u, charge;
        nlohmann::json names = nlohmann::json::array();
        for (const auto& f : files) {
          const logs::Log log = logs::read_log(f.string(), logs::Kind::battery);
          const auto& t = log.col("time_s");
          const auto& q = log.col("charge");
          for (std::size_t i = 0; i < t.size(); ++i) {
            u.push_back(t[i] / kHourS);
            charge.push_back(q[i]);
          }
          names.push_back(f.filename().string());
        }
        const std::vector<double> start{0.0, 0.0, 0.0, 1.0};
        const std::vector<std::string> pnames{"a_per_h3", "b_per_h2", "c_per_h", "d"};
        const std::vector<fit::Parameter> params = fit::free_parameters(pnames, start);
        const fit::FitResult r = fit::fit_curve(Cubic{}, u, charge, params);
        const double t = median_seconds([&] { fit::fit_curve(Cubic{}, u, charge, params); }, min_seconds);
        std::vector<double> std_errors;
        for (const auto& p : r.parameters) std_errors.push_back(p.std_error);
        // The other paths of the same fit, for where the time goes: Levenberg-Marquardt from the
        // start as for a nonlinear model (one residual block), and that with one block per
        // observation (the default before single_residual_block and linear_start).
        fit::FitOptions generic;
        generic.linear_start = false;
        fit::FitOptions per_observation = generic;
        per_observation.single_residual_block = false;
        nlohmann::json variants;
        for (const auto& [key, o] : {std::pair<std::string, fit::FitOptions>{"lm_from_start", generic},
                                     std::pair<std::string, fit::FitOptions>{"lm_from_start_per_observation", per_observation}}) {
          const fit::FitResult v = fit::fit_curve(Cubic{}, u, charge, params, o);
          const double tv = median_seconds([&] { fit::fit_curve(Cubic{}, u, charge, params, o); }, min_seconds);
          variants[key] = {{"values", v.values()}, {"iterations", v.iterations}, {"seconds", tv}};
        }
        sets.push_back({{"speed_cm_s", speed},
                        {"files", names},
                        {"observations", u.size()},
                        {"values", r.values()},
                        {"std_errors", std_errors},
                        {"usable", r.usable},
                        {"rss", r.rss},
                        {"iterations", r.iterations},
                        {"message", r.message},
                        {"seconds", t},
                        {"variants", variants}});
      }
      out["battery"] = {{"time_unit_s", kHourS}, {"model", "charge = a u^3 + b u^2 + c u + d, u = time_s / 3600"},
                        {"start", {0.0, 0.0, 0.0, 1.0}}, {"sets", sets}};
    }
    std::cout << out.dump(2) << '\n';
  } catch (const std::exception& e) {
    std::cerr << "bench_fit_engine: " << e.what() << '\n';
    return 2;
  }
  return 0;
}
