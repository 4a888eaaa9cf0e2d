// Runs an ARGoS experiment twice in one process, with CSimulator::Reset() between the runs (what
// ARGoS's Qt "reset" button and any batch driver that repeats trials do), and writes each run's
// readings, tick by tick, so that reset.sh can require the two runs to be the same.
//
// ARGoS's contract for Reset is that the experiment starts again from its initial state: the
// robots at their initial poses, the random generators reseeded, every sensor and actuator as
// after Init. The first run starts from Init, so it is the expected value of the second.
//
// Every e-puck2 in the arena must run the recorder controller (libepuck2_argos_protocols). Each
// tick, before the space is updated, each robot is given the wheel command of a fixed profile
// (a start, a turn, a stop, a reverse), so that every state a drive keeps (the wheels' speeds
// under accel_limit, the body's lag, the ToF's delay line, the encoders' registers, the battery's
// charge and its position) is away from its initial value when Reset comes.
//   usage: argos_reset_check EXPERIMENT.argos TICKS FIRST.csv SECOND.csv
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <argos3/core/simulator/simulator.h>
#include <argos3/core/simulator/space/space.h>
#include <argos3/core/utility/configuration/argos_exception.h>
#include <argos3/core/utility/plugins/dynamic_loading.h>
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_entity.h>

#include "../experiments/src/recorder_controller.hpp"

namespace {

using namespace argos;

/// The command at tick k (cm/s): none at the first tick (the wheels run on what the actuator
/// holds: nothing after Init, and nothing after Reset), then forward at 9, a turn, a stop, a
/// reverse. Returns false when there is no command.
bool Command(int k, Real& left, Real& right) {
  if (k == 0) return false;
  if (k < 30) {
    left = right = 9.0;
  } else if (k < 50) {
    left = 4.0;
    right = 11.0;
  } else if (k < 60) {
    left = right = 0.0;
  } else {
    left = right = -6.0;
  }
  return true;
}

std::string Num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

void Run(CSimulator& sim, int ticks, const std::string& path) {
  std::ofstream out(path);
  out << "tick,robot,left_steps,right_steps,tof_mm,charge,x_m,y_m,yaw_rad\n";
  CSpace::TMapPerType& robots = sim.GetSpace().GetEntitiesByType("e-puck2");
  for (int k = 0; k < ticks; ++k) {
    Real left = 0, right = 0;
    if (Command(k, left, right))
      for (auto& it : robots) {
        auto* robot = any_cast<CEPuck2Entity*>(it.second);
        dynamic_cast<CEPuck2RecorderController&>(robot->GetControllableEntity().GetController()).SetWheels(left, right);
      }
    sim.UpdateSpace();
    for (auto& it : robots) {
      auto* robot = any_cast<CEPuck2Entity*>(it.second);
      auto& c = dynamic_cast<CEPuck2RecorderController&>(robot->GetControllableEntity().GetController());
      const auto& anchor = robot->GetEmbodiedEntity().GetOriginAnchor();
      CRadians yaw, pitch, roll;
      anchor.Orientation.ToEulerAngles(yaw, pitch, roll);
      out << k << ',' << robot->GetId() << ',' << c.LeftSteps() << ',' << c.RightSteps() << ',' << c.Tof() << ','
          << Num(c.Charge()) << ',' << Num(anchor.Position.GetX()) << ',' << Num(anchor.Position.GetY()) << ','
          << Num(yaw.GetValue()) << '\n';
    }
  }
  out.flush();
  if (!out) {
    std::fprintf(stderr, "argos_reset_check: cannot write %s\n", path.c_str());
    std::exit(1);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: %s EXPERIMENT.argos TICKS FIRST.csv SECOND.csv\n", argv[0]);
    return 2;
  }
  const int ticks = std::atoi(argv[2]);
  try {
    /* as the argos3 program does: every plug-in on ARGOS_PLUGIN_PATH (the calibrated models) */
    CDynamicLoading::LoadAllLibraries();
    CSimulator& sim = CSimulator::GetInstance();
    sim.SetExperimentFileName(argv[1]);
    sim.LoadExperiment();
    Run(sim, ticks, argv[3]);
    sim.Reset();
    Run(sim, ticks, argv[4]);
    sim.Destroy();
  } catch (CARGoSException& ex) {
    std::fprintf(stderr, "argos_reset_check: %s\n", ex.what());
    return 1;
  }
  return 0;
}
