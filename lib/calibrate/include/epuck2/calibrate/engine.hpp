// The engine's vocabulary (lib/fit) as the per-kind fits use it: the calibration speaks in the
// engine's parameters, observations and results, not in copies of them.
#pragma once

#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/robust.hpp"

namespace epuck2::calibrate {

using fit::Censoring;
using fit::FitOptions;
using fit::FitResult;
using fit::LackOfFit;
using fit::Observation;
using fit::Parameter;
using fit::ParameterEstimate;
using fit::RobotSpread;
using fit::RobustFit;
using fit::RobustOptions;
using fit::scalar_value;

}  // namespace epuck2::calibrate
