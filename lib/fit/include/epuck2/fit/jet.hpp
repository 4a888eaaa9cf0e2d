// The engine's automatic-differentiation scalar, under lib/fit's own name: a model templated on
// its scalar (lib/models' formulas, the diagnosis's kinds, the NIST models) is evaluated with
// `epuck2::fit::Jet<N>` (a value and its derivatives over N parameters) wherever a fit needs its
// derivatives. It is Ceres' Jet, so that what the engine differentiates and what a caller
// differentiates are the same arithmetic; only lib/fit names Ceres.
#pragma once

#include <ceres/jet.h>

namespace epuck2::fit {

/// A value and its derivatives with respect to N parameters (member `a`: the value; `v`: the
/// derivatives, an Eigen vector of N).
template <int N>
using Jet = ceres::Jet<double, N>;

/// The value of a scalar or a Jet (models branch on values, never on derivatives).
inline double value_of(double x) { return x; }
template <int N>
double value_of(const Jet<N>& x) {
  return x.a;
}

}  // namespace epuck2::fit
