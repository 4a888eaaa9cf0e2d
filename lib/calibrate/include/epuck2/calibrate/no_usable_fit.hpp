// What a calibration throws when the data were read but no usable fit came out (the CLI's exit 1).
#pragma once

#include <stdexcept>

namespace epuck2::calibrate {

/// The data were read but no usable fit came out: the message says which fit and why.
struct NoUsableFit : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace epuck2::calibrate
