// epuck2-fit nist DIR [--json] [-o FILE] (-o's old spelling --out still works): fits every NIST StRD nonlinear regression problem
// (*.dat) in DIR from both starting points with the project's fitting layer and reports the log
// relative error of every estimate against its certified value. Exit 0 when the report was
// produced (whatever the digits), 2 for a malformed .dat (file:line:column) or an empty folder.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "app_support.hpp"
#include "commands.hpp"
#include "epuck2/nist/nist.hpp"
#include "epuck2/logs/output.hpp"

namespace epuck2::app {

namespace {
struct NistOptions {
  std::string dir;
  bool json = false;
  std::string out;
};

nlohmann::json to_json(const nist::RunReport& r) {
  nlohmann::json params = nlohmann::json::array();
  for (const auto& p : r.parameters)
    params.push_back({{"name", p.name},
                      {"value", p.value},
                      {"std_error", p.std_error},
                      {"certified", p.certified},
                      {"certified_std_error", p.certified_sd},
                      {"lre", p.lre},
                      {"std_error_lre", p.std_error_lre}});
  return {{"problem", r.problem},
          {"start", r.start},
          {"usable", r.usable},
          {"message", r.message},
          {"iterations", r.iterations},
          {"seconds", r.seconds},
          {"rss", r.rss},
          {"certified_rss", r.certified_rss},
          {"rss_lre", r.rss_lre},
          {"min_lre", r.min_lre},
          {"min_std_error_lre", r.min_std_error_lre},
          {"at_target", r.at_target},
          {"parameters", params}};
}

int run_nist(const NistOptions& o) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(o.dir))
    if (entry.is_regular_file() && entry.path().extension() == ".dat") files.push_back(entry.path());
  if (files.empty()) throw UsageError("no .dat files in " + o.dir);
  // NIST's order (lower, average, higher difficulty); unknown names last (parse rejects them).
  const auto& names = nist::problem_names();
  auto rank = [&](const fs::path& p) {
    return static_cast<std::size_t>(std::find(names.begin(), names.end(), p.stem().string()) - names.begin());
  };
  std::sort(files.begin(), files.end(), [&](const fs::path& a, const fs::path& b) {
    return rank(a) != rank(b) ? rank(a) < rank(b) : a < b;
  });
  std::vector<nist::Problem> problems;
  for (const auto& f : files) problems.push_back(nist::read(f.string()));

  const nist::Target target;
  std::vector<nist::RunReport> runs;
  for (const auto& p : problems)
    for (int start : {1, 2}) runs.push_back(nist::run(p, start, nist::default_options(), target));

  int at_target = 0;
  double min_lre = nist::kCertifiedDigits, min_se = nist::kCertifiedDigits, min_rss = nist::kCertifiedDigits;
  nlohmann::json jruns = nlohmann::json::array();
  for (const auto& r : runs) {
    at_target += r.at_target ? 1 : 0;
    min_lre = std::min(min_lre, r.min_lre);
    min_se = std::min(min_se, r.min_std_error_lre);
    min_rss = std::min(min_rss, r.rss_lre);
    jruns.push_back(to_json(r));
  }
  const std::string summary_line = std::to_string(at_target) + "/" + std::to_string(runs.size()) +
                                   " runs at target (parameter LRE >= " + std::to_string(static_cast<int>(target.parameter_lre)) +
                                   ", standard-error LRE >= " + std::to_string(static_cast<int>(target.std_error_lre)) + ")";
  nlohmann::json j = {{"directory", o.dir},
                      {"target", {{"parameter_lre", target.parameter_lre}, {"std_error_lre", target.std_error_lre}}},
                      {"certified_digits", nist::kCertifiedDigits},
                      {"runs", jruns},
                      {"summary",
                       {{"runs", runs.size()},
                        {"at_target", at_target},
                        {"min_lre", min_lre},
                        {"min_std_error_lre", min_se},
                        {"min_rss_lre", min_rss}}}};
  const std::string text = json_text(j);
  if (!o.out.empty()) {
    logs::write_file_atomically(o.out, text);
    std::cerr << "nist: wrote " << o.out << '\n';
  }
  if (logs::is_standard_output(o.out)) return 0;  // -o -: the JSON report is standard output, alone
  if (o.json) {
    std::cout << text;
    return 0;
  }
  std::printf("%-9s %5s %8s %8s %8s %6s %9s  %s\n", "problem", "start", "min LRE", "min SE", "RSS LRE", "iter", "time ms", "result");
  for (const auto& r : runs)
    std::printf("%-9s %5d %8.2f %8.2f %8.2f %6d %9.3f  %s\n", r.problem.c_str(), r.start, r.min_lre, r.min_std_error_lre,
                r.rss_lre, r.iterations, r.seconds * 1e3, r.at_target ? "OK" : (r.usable ? "FAIL" : ("FAIL: " + r.message).c_str()));
  std::printf("%s; min parameter LRE %.2f, min standard-error LRE %.2f, min RSS LRE %.2f\n", summary_line.c_str(), min_lre,
              min_se, min_rss);
  return 0;
}
}  // namespace

void setup_nist(CLI::App& app, Action& action) {
  auto opts = std::make_shared<NistOptions>();
  CLI::App* sub = app.add_subcommand("nist", "Fit the NIST StRD nonlinear regression problems and report digits against the certified values");
  sub->add_option("dir", opts->dir, "Folder holding the StRD .dat files (tests/data/nist)")->required()->check(CLI::ExistingDirectory);
  sub->add_flag("--json", opts->json, "Print one JSON object instead of the table");
  sub->add_option("-o,--output", opts->out, "Also write the JSON report to FILE, atomically (-: to standard output, in place of the table)")->type_name("FILE")->check(output_file());
  // The spelling published first (docs/cli.md: -o, --out FILE), kept working but not listed.
  sub->add_option("--out", opts->out)->group("")->check(output_file());
  sub->callback([opts, &action] { action = [opts] { return run_nist(*opts); }; });
}

}  // namespace epuck2::app
