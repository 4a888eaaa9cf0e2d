// The solver's own log (Ceres reports through glog), silenced by the programs that fit: fits
// report their own status, and the solver's step-by-step complaints are not for users. Ceres and
// glog stay inside lib/fit: a program calls this instead of naming them.
#pragma once

namespace epuck2::fit {

/// Drops every solver log message below FATAL; with `program` (argv[0]), also initializes the
/// logger under that name (once per process, before the first fit).
void silence_solver_log(const char* program = nullptr);

}  // namespace epuck2::fit
