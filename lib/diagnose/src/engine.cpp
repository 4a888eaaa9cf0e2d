// The diagnosis engine (docs/diagnose.md). The joint-fit engine itself (the Engine class) is in
// engine_detail.hpp, the residual-structure scoring in residual_structure.cpp, the search in
// search.cpp; here, what every kind shares.
#include "engine_detail.hpp"

namespace epuck2::diagnose {

namespace detail {

void add_common_covariates(Problem& p, const std::vector<logs::Log>& logs, const std::vector<std::string>& skip) {
  // Per-row values (rows numbered across all logs), spread to the residuals through Problem::row.
  auto per_residual = [&](const std::vector<double>& per_row) {
    std::vector<double> v(p.row.size());
    for (std::size_t i = 0; i < p.row.size(); ++i) v[i] = per_row[p.row[i]];
    return v;
  };
  std::set<std::string> extras;
  for (const auto& log : logs)
    for (const auto& c : log.extra_numeric_columns())
      if (std::find(skip.begin(), skip.end(), c) == skip.end()) extras.insert(c);
  // A column is a candidate only when every log has it.
  for (const auto& name : extras) {
    bool everywhere = true;
    for (const auto& log : logs) everywhere = everywhere && log.has(name);
    if (!everywhere) continue;
    std::vector<double> rows;
    for (const auto& log : logs)
      for (double x : log.col(name)) rows.push_back(x);
    p.extra_columns.emplace_back(name, per_residual(rows));  // the covariate:NAME effect's, per residual
    p.add_row_covariate(name, std::move(rows));                 // scored: once per row
  }
  std::vector<double> index, which;
  for (std::size_t l = 0; l < logs.size(); ++l)
    for (std::size_t i = 0; i < logs[l].rows(); ++i) {
      index.push_back(static_cast<double>(i));
      which.push_back(static_cast<double>(l));
    }
  p.add_row_covariate("log_row", std::move(index));  // not "row": a camera's image has rows
  if (logs.size() > 1) p.add_row_covariate("log", std::move(which));
}

}  // namespace detail

}  // namespace epuck2::diagnose
