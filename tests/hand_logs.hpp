// Hand-made logs that more than one test file needs, each written from the paper's equations with
// whole-count jitter, never by the project's generators (independent of the code under test).
#pragma once

#include <cmath>
#include <sstream>
#include <string>

namespace epuck2::testing {

/// A camera log by hand (the pinhole of docs/fitting.md): horizontal field of view 60 deg,
/// f = 80 / tan(30 deg) = 138.564 px, centre (80, 60); forward 0.3, 0.4, 0.5 m, lateral and
/// vertical -0.04, 0, 0.04 m; 5 readings each with a jitter {-1, 0, 1, 0, 1} px on px and the same
/// shifted by two frames on py (sd 0.84 px, mean +0.2 px). When `bent`, every reading at forward
/// 0.4 m, lateral 0.04 m sits 25 px to the right of its image. Data row i (from 0) is on line i + 3.
inline std::string hand_camera_log(bool bent = false) {
  const double f = 80.0 / std::tan(30.0 * std::acos(-1.0) / 180.0);
  const int jitter[5] = {-1, 0, 1, 0, 1};
  std::ostringstream o;
  o << "# robot: hand-made\nforward_m,lateral_m,vertical_m,px,py\n";
  for (double x : {0.3, 0.4, 0.5})
    for (double y : {-0.04, 0.0, 0.04})
      for (double z : {-0.04, 0.0, 0.04})
        for (int k = 0; k < 5; ++k) {
          long px = std::lround(80.0 - f * y / x) + jitter[k];
          const long py = std::lround(60.0 - f * z / x) + jitter[(k + 2) % 5];
          if (bent && x == 0.4 && y == 0.04) px += 25;
          o << x << ',' << y << ',' << z << ',' << px << ',' << py << '\n';
        }
  return o.str();
}

}  // namespace epuck2::testing
