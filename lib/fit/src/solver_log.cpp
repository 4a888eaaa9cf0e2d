#include "epuck2/fit/solver_log.hpp"

#include <glog/logging.h>

namespace epuck2::fit {

void silence_solver_log(const char* program) {
  FLAGS_minloglevel = google::GLOG_FATAL;
  if (program != nullptr) google::InitGoogleLogging(program);
}

}  // namespace epuck2::fit
