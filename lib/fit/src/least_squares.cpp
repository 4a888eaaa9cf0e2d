#include "epuck2/fit/least_squares.hpp"
#include "solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace epuck2::fit {

namespace {
const ParameterEstimate& estimate(const FitResult& r, const std::string& name) {
  for (const auto& p : r.parameters)
    if (p.name == name) return p;
  std::string known;
  for (const auto& p : r.parameters) known += (known.empty() ? "" : ", ") + p.name;
  throw std::out_of_range("no parameter named '" + name + "' in this fit (its parameters are: " +
                          (known.empty() ? std::string("none") : known) + ")");
}
}  // namespace

double FitResult::value(const std::string& name) const { return estimate(*this, name).value; }

double FitResult::std_error(const std::string& name) const { return estimate(*this, name).std_error; }

std::vector<double> FitResult::values() const {
  std::vector<double> v;
  for (const auto& p : parameters) v.push_back(p.value);
  return v;
}

ceres::LossFunction* make_loss(const FitOptions& options) {
  return options.robust ? new ceres::HuberLoss(options.robust_scale) : nullptr;
}

ceres::Solver::Options solver_options(const FitOptions& options) {
  ceres::Solver::Options o;
  o.linear_solver_type = options.linear_solver == FitOptions::LinearSolver::dense_normal_cholesky ? ceres::DENSE_NORMAL_CHOLESKY
                                                                                                : ceres::DENSE_QR;
  o.max_num_iterations = options.max_iterations;
  o.function_tolerance = options.function_tolerance;
  o.gradient_tolerance = options.gradient_tolerance;
  o.parameter_tolerance = options.parameter_tolerance;
  o.minimizer_progress_to_stdout = false;
  o.logging_type = ceres::SILENT;
  o.num_threads = 1;
  return o;
}

namespace {
// Initial trust-region radius of the cautious strategy (Ceres' default is 1e4): small enough that
// the first steps stay near the start; found on NIST BoxBOD start 1, where 1e-2 and above jump
// to the saturated plateau and 1e-4 converges to the certified minimum.
constexpr double kCautiousTrustRegionRadius = 1e-4;
// Relative difference below which two final costs are taken as equal (about 450 ulp).
constexpr double kSameCostRelative = 1e-13;

// The values of every parameter block of a problem, to go back to a start or keep a best point.
struct Snapshot {
  std::vector<double*> blocks;
  std::vector<std::vector<double>> values;
};

Snapshot take_snapshot(const ceres::Problem& problem) {
  Snapshot s;
  problem.GetParameterBlocks(&s.blocks);
  for (double* b : s.blocks) s.values.emplace_back(b, b + problem.ParameterBlockSize(b));
  return s;
}

void restore(const Snapshot& s) {
  for (std::size_t i = 0; i < s.blocks.size(); ++i) std::copy(s.values[i].begin(), s.values[i].end(), s.blocks[i]);
}

// Relative size, against the largest pivot, below which a pivot of the column-equilibrated
// Jacobian counts as zero in the full-rank check (looser than Eigen's default of n ulp).
constexpr double kRankThreshold = 1e-10;
// A parameter whose relative change moves the residuals this many times less than another's
// does (|b_j| |J_j| against the largest |b_k| |J_k|) is taken as stuck where the model no longer
// depends on it.
constexpr double kStuckSensitivity = 1e-8;

// The checks the first strategy's solution must pass for the other strategies to be skipped:
// Ceres reports convergence, the restarts stopped because the cost no longer fell (not because
// they ran out), every parameter still moves the residuals (a solver stopped on a plateau where
// the model saturates, as NIST BoxBOD from start 1 where exp(-b2 x) underflows for every x, has
// a parameter that does not), and the Jacobian with its columns equilibrated has full column
// rank. A problem with a manifold (parameters held) is not checked: every strategy runs.
bool passes_own_checks(ceres::Problem& problem, const ceres::Solver::Summary& s, bool still_falling) {
  if (s.termination_type != ceres::CONVERGENCE || still_falling || !std::isfinite(s.final_cost)) return false;
  std::vector<double*> blocks;
  problem.GetParameterBlocks(&blocks);
  std::vector<double> values;
  for (double* b : blocks) {
    if (problem.GetManifold(b) != nullptr || problem.IsParameterBlockConstant(b)) return false;
    values.insert(values.end(), b, b + problem.ParameterBlockSize(b));
  }
  ceres::CRSMatrix crs;
  double cost = 0;
  if (!problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, &crs)) return false;
  if (crs.num_cols == 0) return true;
  if (static_cast<std::size_t>(crs.num_cols) != values.size()) return false;
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r)
    for (int k = crs.rows[static_cast<std::size_t>(r)]; k < crs.rows[static_cast<std::size_t>(r) + 1]; ++k)
      j(r, crs.cols[static_cast<std::size_t>(k)]) = crs.values[static_cast<std::size_t>(k)];
  if (!j.allFinite()) return false;
  double largest = 0;
  std::vector<double> sensitivity(values.size());
  for (Eigen::Index c = 0; c < j.cols(); ++c) {
    sensitivity[static_cast<std::size_t>(c)] = std::abs(values[static_cast<std::size_t>(c)]) * j.col(c).norm();
    largest = std::max(largest, sensitivity[static_cast<std::size_t>(c)]);
  }
  for (double v : sensitivity)
    if (!(v > kStuckSensitivity * largest)) return false;
  for (Eigen::Index c = 0; c < j.cols(); ++c) {
    const double norm = j.col(c).norm();
    if (!(norm > 0)) return false;
    j.col(c) /= norm;
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(j);
  qr.setThreshold(kRankThreshold);
  return qr.rank() == j.cols();
}
}  // namespace

ceres::Solver::Summary solve(ceres::Problem& problem, const FitOptions& options) {
  const ceres::Solver::Options primary = solver_options(options);
  ceres::Solver::Summary summary;
  if (options.restarts <= 0 && !options.try_alternatives) {
    ceres::Solve(primary, &problem, &summary);
    return summary;
  }
  std::vector<ceres::Solver::Options> strategies{primary};
  if (options.try_alternatives) {
    ceres::Solver::Options dogleg = primary;
    dogleg.trust_region_strategy_type = ceres::DOGLEG;
    dogleg.dogleg_type = ceres::TRADITIONAL_DOGLEG;
    strategies.push_back(dogleg);
    ceres::Solver::Options subspace = dogleg;
    subspace.dogleg_type = ceres::SUBSPACE_DOGLEG;
    strategies.push_back(subspace);
    ceres::Solver::Options cholesky = primary;
    cholesky.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    strategies.push_back(cholesky);
    // A cautious first trust region: from a poor start, LM's first step can leap onto a plateau
    // where the model saturates (exp(-b x) = 0 for every x: NIST BoxBOD from start 1) and stop
    // there with a zero gradient.
    ceres::Solver::Options cautious = primary;
    cautious.initial_trust_region_radius = kCautiousTrustRegionRadius;
    strategies.push_back(cautious);
  }
  const Snapshot start = take_snapshot(problem);
  std::vector<ceres::IterationSummary> all_iterations;
  bool have_best = false;
  double best_cost = std::numeric_limits<double>::infinity();
  Snapshot best;
  ceres::Solver::Summary best_summary, first_summary;
  Snapshot first;
  for (std::size_t k = 0; k < strategies.size(); ++k) {
    restore(start);
    ceres::Solver::Summary s;
    ceres::Solve(strategies[k], &problem, &s);
    all_iterations.insert(all_iterations.end(), s.iterations.begin(), s.iterations.end());
    if (k == 0) {
      first_summary = s;
      first = take_snapshot(problem);
    }
    if (!s.IsSolutionUsable() || !std::isfinite(s.final_cost)) continue;
    Snapshot here = take_snapshot(problem);
    bool still_falling = options.restarts > 0;
    for (int r = 0; r < options.restarts; ++r) {
      ceres::Solver::Summary again;
      ceres::Solve(strategies[k], &problem, &again);
      all_iterations.insert(all_iterations.end(), again.iterations.begin(), again.iterations.end());
      if (!again.IsSolutionUsable() || !(again.final_cost < s.final_cost)) {
        still_falling = false;
        break;
      }
      s = again;
      here = take_snapshot(problem);
    }
    // The other strategies are spent only where the first one's solution fails its own checks.
    if (k == 0) {
      restore(here);
      if (passes_own_checks(problem, s, still_falling)) {
        s.iterations = all_iterations;
        return s;
      }
    }
    // Another strategy wins only when clearly lower: costs within rounding are the same minimum
    // (or a mirror image of it, as Eckerle4's (b1, b2) -> (-b1, -b2)), and the first one stays.
    if (!have_best || s.final_cost < best_cost * (1.0 - kSameCostRelative)) {
      best_cost = s.final_cost;
      best = here;
      best_summary = s;
      have_best = true;
    }
  }
  if (!have_best) {
    restore(first);
    first_summary.iterations = all_iterations;
    return first_summary;
  }
  restore(best);
  best_summary.iterations = all_iterations;
  return best_summary;
}

namespace {
// The columns of a Jacobian scaled to unit norm and their column-pivoted QR: what the covariance,
// the identifiability check and the linear least-squares start factor, so that they give the same
// digits. The factorization runs in place on the scaled copy (one n x m buffer, not two); with
// `cols`, of those columns only (no second copy of them first).
struct EquilibratedQR {
  Eigen::VectorXd scale;
  Eigen::MatrixXd factors;  // the equilibrated columns, overwritten by the QR factors
  Eigen::ColPivHouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr;

  explicit EquilibratedQR(const Eigen::MatrixXd& jacobian, const std::vector<Eigen::Index>* cols = nullptr)
      : scale(cols != nullptr ? static_cast<Eigen::Index>(cols->size()) : jacobian.cols()),
        factors(equilibrated(jacobian, cols, &scale)),
        qr(factors) {}
  EquilibratedQR(const EquilibratedQR&) = delete;
  EquilibratedQR& operator=(const EquilibratedQR&) = delete;

  static Eigen::MatrixXd equilibrated(const Eigen::MatrixXd& jacobian, const std::vector<Eigen::Index>* cols,
                                      Eigen::VectorXd* scale) {
    const Eigen::Index m = scale->size();
    Eigen::MatrixXd Jf(jacobian.rows(), m);
    for (Eigen::Index c = 0; c < m; ++c) {
      const auto column = jacobian.col(cols != nullptr ? (*cols)[static_cast<std::size_t>(c)] : c);
      const double norm = column.norm();
      (*scale)(c) = norm > 0 ? 1.0 / norm : 1.0;
      Jf.col(c) = column * (*scale)(c);
    }
    return Jf;
  }
  bool full_rank() const { return qr.rank() == scale.size(); }
  // (J^T J)^-1 = S (Jf^T Jf)^-1 S with (Jf^T Jf)^-1 = P R^-1 R^-T P^T.
  Eigen::MatrixXd inverse_normal() const {
    const Eigen::Index m = scale.size();
    const Eigen::MatrixXd R = qr.matrixR().topLeftCorner(m, m).triangularView<Eigen::Upper>();
    const Eigen::MatrixXd Rinv = R.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(m, m));
    const Eigen::MatrixXd inner = Rinv * Rinv.transpose();
    const Eigen::MatrixXd P = qr.colsPermutation();
    return scale.asDiagonal() * (P * inner * P.transpose()) * scale.asDiagonal();
  }
  // The condition number of the equilibrated normal matrix Jf^T Jf (the square of R's, infinite
  // when R is singular) and its least-determined direction over the columns: Jf = Q R P^T and
  // R = U S V_R^T give Jf's right singular vectors P V_R, the last for the smallest value.
  double smallest_direction(Eigen::VectorXd* direction) const {
    const Eigen::Index m = scale.size(), k = std::min(factors.rows(), m);
    Eigen::MatrixXd R = qr.matrixR().topRows(k);
    for (Eigen::Index c = 0; c < m; ++c)
      for (Eigen::Index row = c + 1; row < k; ++row) R(row, c) = 0;
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(R, Eigen::ComputeFullV);
    *direction = qr.colsPermutation() * svd.matrixV().col(m - 1);
    const double hi = svd.singularValues()(0);
    const double lo = k < m ? 0.0 : svd.singularValues()(m - 1);
    return lo > 0 ? (hi / lo) * (hi / lo) : std::numeric_limits<double>::infinity();
  }
};

// Why a parameter's standard error stays NaN (ParameterEstimate::std_error_why): a free column of
// zeros (the data do not depend on it), or no degrees of freedom left over the estimable columns
// `cols`; the estimable ones get a provisional reason that the covariance clears.
void explain_undetermined(FitResult& r, Eigen::Index n_rows, const std::vector<bool>& free_column,
                          const std::vector<bool>& zero_column, const std::vector<Eigen::Index>& cols) {
  const std::size_t n = static_cast<std::size_t>(n_rows);
  for (std::size_t j = 0; j < zero_column.size() && j < r.parameters.size(); ++j) {
    ParameterEstimate& p = r.parameters[j];
    const bool is_free = j >= free_column.size() || free_column[j];
    if (!is_free) continue;
    if (zero_column[j])
      p.std_error_why = "not identifiable: the model does not depend on " + p.name +
                        " at the solution on these data (its Jacobian column is zero)";
    else if (n <= cols.size())
      p.std_error_why = "undefined: " + std::to_string(n) + " residuals for " + std::to_string(cols.size()) +
                        " estimable parameters leave no degree of freedom to estimate the noise";
    else
      p.std_error_why = "the covariance was not computed";
  }
}

void explain_rank_deficient(FitResult& r, const std::vector<Eigen::Index>& cols) {
  for (Eigen::Index j : cols)
    if (static_cast<std::size_t>(j) < r.parameters.size()) {
      ParameterEstimate& p = r.parameters[static_cast<std::size_t>(j)];
      p.std_error_why = "not identifiable: these data do not determine " + p.name +
                        " separately from the other parameters (rank-deficient Jacobian)";
    }
}
}  // namespace

Identifiability check_identifiability(const Eigen::MatrixXd& jacobian, const std::vector<bool>& free_column,
                                      double max_condition, const Eigen::MatrixXd* inverse_normal_given) {
  Identifiability id;
  for (Eigen::Index j = 0; j < jacobian.cols(); ++j) {
    if (static_cast<std::size_t>(j) < free_column.size() && !free_column[static_cast<std::size_t>(j)]) continue;
    if (jacobian.col(j).squaredNorm() > 0)
      id.estimable.push_back(j);
    else
      id.undetermined.push_back({j, Identifiability::Why::zero_column, 1.0});
  }
  const auto m = static_cast<Eigen::Index>(id.estimable.size());
  if (m == 0) return id;
  if (inverse_normal_given != nullptr && inverse_normal_given->rows() == m && inverse_normal_given->cols() == m) {
    id.rank = m;
    id.inverse_normal = *inverse_normal_given;
    return id;
  }
  const bool every_column = m == jacobian.cols();
  const EquilibratedQR f(jacobian, every_column ? nullptr : &id.estimable);
  id.rank = f.qr.rank();
  bool weak = id.rank_deficient();
  if (weak || std::isfinite(max_condition)) {
    Eigen::VectorXd v;
    id.condition = f.smallest_direction(&v);
    weak = weak || !(id.condition <= max_condition);
    if (weak) {
      const Eigen::VectorXd a = v.cwiseAbs();
      const double largest = a.maxCoeff();
      const auto why = id.rank_deficient() ? Identifiability::Why::rank_deficient : Identifiability::Why::condition;
      for (Eigen::Index c = 0; c < m; ++c)
        if (a(c) >= kAlongShare * largest) id.undetermined.push_back({id.estimable[static_cast<std::size_t>(c)], why, a(c) / largest});
      std::sort(id.undetermined.begin(), id.undetermined.end(),
                [](const Identifiability::Column& x, const Identifiability::Column& y) { return x.column < y.column; });
    }
  }
  if (!weak) id.inverse_normal = f.inverse_normal();
  return id;
}

bool inverse_normal_matrix(const Eigen::MatrixXd& jacobian, Eigen::MatrixXd* inverse) {
  Identifiability id = check_identifiability(jacobian, {});
  if (!id.determined()) return false;
  *inverse = std::move(id.inverse_normal);
  return true;
}

bool linear_least_squares(const Eigen::MatrixXd& residual_jacobian, const Eigen::VectorXd& residuals,
                          const std::vector<bool>& free_column, Eigen::VectorXd* step, Eigen::MatrixXd* inverse_normal) {
  const Eigen::Index p = residual_jacobian.cols();
  *step = Eigen::VectorXd::Zero(p);
  std::vector<Eigen::Index> cols;
  for (Eigen::Index j = 0; j < p; ++j)
    if (static_cast<std::size_t>(j) >= free_column.size() || free_column[static_cast<std::size_t>(j)]) cols.push_back(j);
  const auto m = static_cast<Eigen::Index>(cols.size());
  if (m == 0 || residual_jacobian.rows() <= m) return false;
  // A free column of zeros leaves its parameter undetermined: no linear start (estimable_columns
  // would drop it from the covariance).
  for (Eigen::Index c : cols)
    if (!(residual_jacobian.col(c).squaredNorm() > 0)) return false;
  const EquilibratedQR f(residual_jacobian, m == p ? nullptr : &cols);
  if (!f.full_rank()) return false;
  // residuals + J step is minimal at step = -J^+ residuals; in equilibrated columns step = S z.
  const Eigen::VectorXd z = f.qr.solve(residuals);
  for (Eigen::Index c = 0; c < m; ++c) (*step)(cols[static_cast<std::size_t>(c)]) = -z(c) * f.scale(c);
  if (!step->allFinite()) return false;
  if (inverse_normal) *inverse_normal = f.inverse_normal();
  return true;
}

bool normal_equations_least_squares(const Eigen::MatrixXd& normal, const Eigen::VectorXd& gradient,
                                    const std::vector<bool>& free_column, Eigen::VectorXd* step,
                                    Eigen::MatrixXd* inverse_normal) {
  const Eigen::Index p = normal.cols();
  *step = Eigen::VectorXd::Zero(p);
  std::vector<Eigen::Index> cols;
  for (Eigen::Index j = 0; j < p; ++j)
    if (static_cast<std::size_t>(j) >= free_column.size() || free_column[static_cast<std::size_t>(j)]) cols.push_back(j);
  const auto m = static_cast<Eigen::Index>(cols.size());
  if (m == 0) return false;
  // Equilibrated: G = S (J^T J) S with unit diagonal, g = S J^T r (S = diag(1 / |J_j|)).
  Eigen::VectorXd scale(m), g(m);
  for (Eigen::Index a = 0; a < m; ++a) {
    const double d = normal(cols[static_cast<std::size_t>(a)], cols[static_cast<std::size_t>(a)]);
    if (!(d > 0) || !std::isfinite(d)) return false;
    scale(a) = 1.0 / std::sqrt(d);
  }
  Eigen::MatrixXd G(m, m);
  for (Eigen::Index a = 0; a < m; ++a) {
    const Eigen::Index ca = cols[static_cast<std::size_t>(a)];
    g(a) = gradient(ca) * scale(a);
    for (Eigen::Index b = 0; b <= a; ++b) {
      const Eigen::Index cb = cols[static_cast<std::size_t>(b)];
      G(a, b) = G(b, a) = normal(std::max(ca, cb), std::min(ca, cb)) * scale(a) * scale(b);
    }
  }
  if (!G.allFinite() || !g.allFinite()) return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(G, Eigen::EigenvaluesOnly);
  if (eig.info() != Eigen::Success) return false;
  const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
  if (!(lo > 0) || !(hi <= lo * kNormalEquationsMaxCondition)) return false;
  const Eigen::LLT<Eigen::MatrixXd> llt(G);
  if (llt.info() != Eigen::Success) return false;
  // residuals + J step is minimal at step = -(J^T J)^-1 J^T residuals; in equilibrated columns
  // step = S z with G z = -g.
  const Eigen::VectorXd z = llt.solve(-g);
  for (Eigen::Index c = 0; c < m; ++c) (*step)(cols[static_cast<std::size_t>(c)]) = z(c) * scale(c);
  if (!step->allFinite()) return false;
  if (inverse_normal) {
    const Eigen::MatrixXd Ginv = llt.solve(Eigen::MatrixXd::Identity(m, m));
    *inverse_normal = scale.asDiagonal() * Ginv * scale.asDiagonal();
  }
  return true;
}

namespace {
// The policy of set_covariance and summarize on the one identifiability check (explained NaN):
// column c of `jacobian` is parameter param_of[c] (`total` in all; param_of empty: c itself),
// free where `free_in_jacobian` says so (true beyond its end); `is_free` says it per parameter
// (true beyond its end). A free zero column keeps NaN with its reason; no degree of freedom
// left, or rank-deficient estimable columns, leave every estimable one NaN with the reason.
// `inverse_normal`, when of the estimable columns' size, is their (J^T J)^-1 already computed.
void covariance_over(FitResult& r, Eigen::Index total, const Eigen::MatrixXd& jacobian, const std::vector<bool>& free_in_jacobian,
                     const std::vector<Eigen::Index>& param_of, const std::vector<bool>& is_free,
                     const Eigen::MatrixXd* inverse_normal) {
  const Identifiability id = check_identifiability(jacobian, free_in_jacobian, std::numeric_limits<double>::infinity(), inverse_normal);
  auto parameter = [&](Eigen::Index c) { return param_of.empty() ? c : param_of[static_cast<std::size_t>(c)]; };
  std::vector<bool> zero_column(static_cast<std::size_t>(total), false);
  for (const Identifiability::Column& u : id.undetermined)
    if (u.why == Identifiability::Why::zero_column) zero_column[static_cast<std::size_t>(parameter(u.column))] = true;
  std::vector<Eigen::Index> cols;  // the estimable parameters
  for (Eigen::Index c : id.estimable) cols.push_back(parameter(c));
  const auto n = jacobian.rows();
  const auto m = static_cast<Eigen::Index>(cols.size());
  explain_undetermined(r, n, is_free, zero_column, cols);
  if (m == 0 || n <= m) return;
  const double s2 = r.rss / static_cast<double>(n - m);
  if (id.inverse_normal.size() == 0) {
    r.covariance = Eigen::MatrixXd::Zero(total, total);
    r.message += " (covariance rank-deficient, rank " + std::to_string(id.rank) + " of " + std::to_string(m) +
                 ": standard errors unavailable)";
    explain_rank_deficient(r, cols);
    return;
  }
  const Eigen::MatrixXd& covf = id.inverse_normal;
  r.covariance = Eigen::MatrixXd::Zero(total, total);
  for (Eigen::Index j : cols)
    if (static_cast<std::size_t>(j) < r.parameters.size()) r.parameters[static_cast<std::size_t>(j)].std_error_why.clear();
  for (Eigen::Index a = 0; a < m; ++a)
    for (Eigen::Index b = 0; b < m; ++b)
      r.covariance(cols[static_cast<std::size_t>(a)], cols[static_cast<std::size_t>(b)]) = covf(a, b) * s2;
  for (Eigen::Index j : cols)
    if (static_cast<std::size_t>(j) < r.parameters.size())
      r.parameters[static_cast<std::size_t>(j)].std_error = std::sqrt(std::max(0.0, r.covariance(j, j)));
  for (Eigen::Index j = 0; j < total; ++j)
    if (static_cast<std::size_t>(j) < is_free.size() && !is_free[static_cast<std::size_t>(j)] &&
        static_cast<std::size_t>(j) < r.parameters.size())
      r.parameters[static_cast<std::size_t>(j)].std_error = 0.0;
}
}  // namespace

void set_covariance(FitResult& r, const Eigen::MatrixXd& jacobian, const std::vector<bool>& free_column,
                    const Eigen::MatrixXd* inverse_normal) {
  covariance_over(r, jacobian.cols(), jacobian, free_column, {}, free_column, inverse_normal);
}

void set_rss(FitResult& r, double rss) {
  const double n = static_cast<double>(r.observations);
  const double old_variance = r.residual_variance;
  const double tss = r.rss > 0 && std::isfinite(r.r2) && r.r2 < 1 ? r.rss / (1.0 - r.r2) : std::numeric_limits<double>::quiet_NaN();
  r.rss = rss;
  r.mse = n > 0 ? rss / n : 0.0;
  r.residual_variance = n > r.free_parameters ? rss / (n - r.free_parameters) : std::numeric_limits<double>::quiet_NaN();
  if (std::isfinite(tss) && tss > 0) r.r2 = 1.0 - rss / tss;
  r.aic = akaike(r.observations, rss, r.free_parameters);
  r.bic = bayes(r.observations, rss, r.free_parameters);
  if (old_variance > 0 && std::isfinite(old_variance) && r.covariance.size() > 0) {
    const double ratio = r.residual_variance / old_variance;
    r.covariance *= ratio;
    for (auto& p : r.parameters)
      if (std::isfinite(p.std_error)) p.std_error *= std::sqrt(ratio);
  }
}

double akaike(std::size_t n, double rss, int k) {
  const double nn = static_cast<double>(n);
  return nn * std::log(std::max(rss, std::numeric_limits<double>::min()) / nn) + 2.0 * k;
}

double bayes(std::size_t n, double rss, int k) {
  const double nn = static_cast<double>(n);
  return nn * std::log(std::max(rss, std::numeric_limits<double>::min()) / nn) + k * std::log(nn);
}

namespace {
// Sums over thousands of rows in four interleaved partial sums (element i into partial i mod 4,
// then (s0 + s1) + (s2 + s3)): a fixed order, so the same digits on every run, and four
// independent chains of additions instead of one, each waiting on the last.
double sum(const std::vector<double>& v) {
  double s[4] = {0, 0, 0, 0};
  const std::size_t n = v.size(), n4 = n - n % 4;
  for (std::size_t i = 0; i < n4; i += 4)
    for (std::size_t k = 0; k < 4; ++k) s[k] += v[i + k];
  for (std::size_t i = n4; i < n; ++i) s[i - n4] += v[i];
  return (s[0] + s[1]) + (s[2] + s[3]);
}

// Sum of (v_i - shift)^2, in the same order as sum().
double sum_of_squares(const std::vector<double>& v, double shift) {
  double s[4] = {0, 0, 0, 0};
  const std::size_t n = v.size(), n4 = n - n % 4;
  for (std::size_t i = 0; i < n4; i += 4)
    for (std::size_t k = 0; k < 4; ++k) s[k] += (v[i + k] - shift) * (v[i + k] - shift);
  for (std::size_t i = n4; i < n; ++i) s[i - n4] += (v[i] - shift) * (v[i] - shift);
  return (s[0] + s[1]) + (s[2] + s[3]);
}

// Everything summarize reports except the covariance, from the residuals at the solution:
// parameters (NaN standard errors), RSS, MSE, residual variance, R^2, AIC, BIC, usable and why
// not. Returns which scalars are free (blocks flagged constant are not).
std::vector<bool> statistics(FitResult& r, const ParameterLayout& layout, const std::vector<bool>& constant_block,
                             const std::vector<double>& residuals, bool evaluated,
                             const std::vector<double>& observations, int iterations, const std::string& message,
                             bool solution_usable) {
  r.iterations = iterations;
  r.message = message;
  const std::size_t n = residuals.size();
  r.observations = n;
  const double rss = sum_of_squares(residuals, 0.0);
  const double sum_y = sum(observations);
  r.rss = rss;
  r.mse = n ? rss / static_cast<double>(n) : 0.0;

  // Parameters, and which scalars are free (constant blocks and subset manifolds are not).
  int total = 0;
  for (int s : layout.sizes) total += s;
  std::vector<bool> is_free(static_cast<std::size_t>(total), true);
  {
    int offset = 0;
    for (std::size_t b = 0; b < layout.blocks.size(); ++b) {
      const bool constant = b < constant_block.size() && constant_block[b];
      for (int j = 0; j < layout.sizes[b]; ++j) {
        r.parameters.push_back({layout.names.size() > static_cast<std::size_t>(offset + j)
                                    ? layout.names[static_cast<std::size_t>(offset + j)]
                                    : "p" + std::to_string(offset + j),
                                layout.blocks[b][j], std::numeric_limits<double>::quiet_NaN()});
        if (constant) is_free[static_cast<std::size_t>(offset + j)] = false;
      }
      offset += layout.sizes[b];
    }
  }
  int k = 0;
  for (bool f : is_free) k += f ? 1 : 0;
  r.free_parameters = k;

  r.residual_variance = n > static_cast<std::size_t>(k) ? rss / static_cast<double>(n - static_cast<std::size_t>(k))
                                                        : std::numeric_limits<double>::quiet_NaN();
  r.aic = akaike(n, rss, k);
  r.bic = bayes(n, rss, k);
  if (!observations.empty()) {
    const double tss = sum_of_squares(observations, sum_y / static_cast<double>(observations.size()));
    r.r2 = tss > 0 ? 1.0 - rss / tss : std::numeric_limits<double>::quiet_NaN();
  } else {
    r.r2 = std::numeric_limits<double>::quiet_NaN();
  }

  const bool converged = solution_usable && std::isfinite(rss);
  r.usable = evaluated && converged;
  if (!evaluated) r.message = "the model could not be evaluated at the solution";
  for (auto& p : r.parameters)
    p.std_error_why = r.usable ? "the covariance was not computed" : "the fit is not usable: " + r.message;
  return is_free;
}
}  // namespace

FitResult summarize(const ParameterLayout& layout, const std::vector<double>& residuals, bool evaluated,
                    const std::vector<double>& observations, int iterations, const std::string& message, bool usable) {
  FitResult r;
  statistics(r, layout, {}, residuals, evaluated, observations, iterations, message, usable);
  return r;
}

FitResult summarize(ceres::Problem& problem, const ParameterLayout& layout,
                    const std::vector<double>& observations, const ceres::Solver::Summary& summary,
                    const FitOptions& options) {
  return summarize(problem, layout, observations, static_cast<int>(summary.iterations.size()), summary.message,
                   summary.IsSolutionUsable(), options);
}

FitResult summarize(ceres::Problem& problem, const ParameterLayout& layout, const std::vector<double>& observations,
                    int iterations, const std::string& message, bool usable, const FitOptions& options) {
  std::vector<bool> constant_block;
  std::vector<double*> free_blocks;
  std::vector<int> free_offset;  // each free block's first scalar among all parameters
  {
    int offset = 0;
    for (std::size_t b = 0; b < layout.blocks.size(); ++b) {
      constant_block.push_back(problem.IsParameterBlockConstant(layout.blocks[b]));
      if (!constant_block.back()) {
        free_blocks.push_back(layout.blocks[b]);
        free_offset.push_back(offset);
      }
      offset += layout.sizes[b];
    }
  }
  // The Jacobian over the free blocks only: the constant ones would add n columns of zeros each
  // (on a long diagnosis log, hundreds of MB as a sparse matrix and again dense).
  const bool want_jacobian = options.compute_covariance && !free_blocks.empty();
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks = want_jacobian ? free_blocks : layout.blocks;
  eo.apply_loss_function = false;
  eo.num_threads = 1;
  double cost = 0;
  std::vector<double> residuals;
  ceres::CRSMatrix jac;
  const bool evaluated = problem.Evaluate(eo, &cost, &residuals, nullptr, want_jacobian ? &jac : nullptr);

  FitResult r;
  const std::vector<bool> is_free =
      statistics(r, layout, constant_block, residuals, evaluated, observations, iterations, message, usable);
  if (!r.usable) return r;
  const auto n = static_cast<Eigen::Index>(r.observations);
  const auto total = static_cast<Eigen::Index>(is_free.size());

  if (!options.compute_covariance) {
    for (auto& p : r.parameters) p.std_error_why = "standard errors were not asked for";
    return r;
  }
  if (r.free_parameters == 0) return r;
  // Column c of `jac` is scalar param_of[c] of the layout.
  std::vector<Eigen::Index> param_of;
  for (std::size_t b = 0, k = 0; b < layout.blocks.size(); ++b) {
    if (constant_block[b]) continue;
    for (int j = 0; j < layout.sizes[b]; ++j) param_of.push_back(free_offset[k] + j);
    ++k;
  }
  if (jac.num_cols != static_cast<int>(param_of.size()) || jac.num_rows != static_cast<int>(n)) {
    r.message += " (covariance: unexpected Jacobian shape: standard errors unavailable)";
    return r;
  }
  // The one identifiability check on the free columns (a zero column: the data do not depend on
  // the parameter, or a SubsetManifold holds it), then the covariance as set_covariance gives it.
  Eigen::MatrixXd Jf = Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(param_of.size()));
  for (int row = 0; row < jac.num_rows; ++row)
    for (int idx = jac.rows[static_cast<std::size_t>(row)]; idx < jac.rows[static_cast<std::size_t>(row) + 1]; ++idx)
      Jf(row, jac.cols[static_cast<std::size_t>(idx)]) = jac.values[static_cast<std::size_t>(idx)];
  jac = ceres::CRSMatrix();  // no longer needed: not held beside the QR's copies
  covariance_over(r, total, Jf, {}, param_of, is_free, nullptr);
  return r;
}

}  // namespace epuck2::fit
