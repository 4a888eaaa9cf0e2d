// The `calibrated` battery discharge model: the E-Puck2 plug-in's four models (simple, linear,
// cubic, approximated) with tables fitted by epuck2-fit (battery.json), through the plug-in's
// discharge-model factory, the arithmetic being epuck2::models::battery::step.
//
//   <epuck2 id="ep0">
//     <epuck2_battery discharge_model="calibrated" coefficients="battery.json"
//                     [model="cubic"] behaviour="argos" [tables="file|plugin"] start_charge="1.0"/>
//
// The file may have some speeds only (a battery calibrated from a few runs): its tables there,
// the plug-in's elsewhere, said at Init. A diagnosis's battery_model is the model when the XML
// names none, and its effects.capacity_scale.k scales the capacity (time runs 1/k as fast).
// tables="plugin": the plug-in's tables with the file's capacity scale (one or two runs).
//
// behaviour="argos": Behaviour::argos_compatible, bit for bit the plug-in's arithmetic (with the
// plug-in's own tables it reproduces its models exactly); behaviour="corrected": the project's
// corrections (docs/battery-models.md). The distance a tick's speed is computed from is the
// plug-in's: the body's displacement, or for an in-place rotation the angle times 0.0265f.
#include <argos3/core/simulator/entity/composable_entity.h>
#include <argos3/core/simulator/entity/embodied_entity.h>
#include <argos3/core/simulator/physics_engine/physics_engine.h>
#include <argos3/core/simulator/simulator.h>
#include <argos3/core/utility/string_utilities.h>
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_battery_equipped_entity.h>

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <vector>

#include <epuck2/models/battery.hpp>

#include <epuck2/coefficients/model_file.hpp>
#include <epuck2/coefficients/model_sets.hpp>
#include <epuck2/models/effects.hpp>

#include "applied_effects.hpp"

namespace argos {

namespace mb = epuck2::models::battery;

/// "0, 2..5, 9" for a list of whole speeds.
std::string Speeds(const std::vector<int>& v) {
  std::ostringstream os;
  for (std::size_t i = 0; i < v.size();) {
    std::size_t j = i;
    while (j + 1 < v.size() && v[j + 1] == v[j] + 1) ++j;
    os << (i ? ", " : "") << v[i];
    if (j > i) os << (j == i + 1 ? ", " : "..") << v[j];
    i = j + 1;
  }
  return os.str();
}

/// A battery file as the calibrated model runs it: the file's tables at its speeds, the plug-in's
/// elsewhere, read by the project's one reader (lib/coefficients).
struct SBatteryFile {
  mb::Tables Tables;
  epuck2::coefficients::TableSources Sources;
  bool HasModel = false;  ///< the file names its battery_model
  mb::Model Model = mb::Model::cubic;
  double CapacityK = 1.0;  ///< effects.capacity_scale.k (1: none)
};

/// The file read once per process (while it stays the same) and shared: 50 robots step through
/// one copy of the tables, not 50. A covariate stops ARGoS at Init (no log column in ARGoS).
std::shared_ptr<const SBatteryFile> SharedBatteryFile(const std::string& str_path) {
  static std::mutex cMutex;
  static std::map<std::string, std::pair<std::shared_ptr<const nlohmann::json>, std::shared_ptr<const SBatteryFile>>> mapCache;
  const auto pcRoot = epuck2::coefficients::shared_json_file(str_path);
  std::lock_guard<std::mutex> cLock(cMutex);
  const auto it = mapCache.find(str_path);
  if (it != mapCache.end() && it->second.first == pcRoot) return it->second.second;
  auto pcFile = std::make_shared<SBatteryFile>();
  const auto sModel = epuck2::coefficients::battery_model_from_json(*pcRoot, str_path, "", pcFile->Sources);
  if (!sModel.covariates.empty()) {
    const std::string strName = std::string(epuck2::models::effects::kCovariatePrefix) + sModel.covariates.front().column;
    epuck2::coefficients::fail_in_file(str_path, "/effects/" + strName,
                                        "effects." + strName + ": the calibrated battery cannot apply it in ARGoS: it needs "
                                        "the log column '" + sModel.covariates.front().column + "', which ARGoS does not have");
  }
  /* an effect the battery does not apply would be ignored: refused (applied_effects.hpp) */
  epuck2::argos_plugin::refuse_unapplied(sModel, epuck2::argos_plugin::battery_applies(), *pcRoot, str_path, "",
                                         "the calibrated battery");
  pcFile->Tables = sModel.tables;
  pcFile->HasModel = pcRoot->contains("battery_model");
  pcFile->Model = sModel.model;
  pcFile->CapacityK = sModel.capacity.k;
  mapCache[str_path] = {pcRoot, pcFile};
  return pcFile;
}

class CEPuck2BatteryDischargeModelCalibrated : public CEPuck2BatteryDischargeModel {
 public:
  void Init(TConfigurationNode& t_tree) override {
    std::string strFile, strModel, strBehaviour = "argos", strTables = "file";
    GetNodeAttributeOrDefault(t_tree, "coefficients", strFile, strFile);
    GetNodeAttributeOrDefault(t_tree, "model", strModel, strModel);
    GetNodeAttributeOrDefault(t_tree, "behaviour", strBehaviour, strBehaviour);
    GetNodeAttributeOrDefault(t_tree, "tables", strTables, strTables);
    if (strTables != "file" && strTables != "plugin")
      THROW_ARGOSEXCEPTION("calibrated battery: tables must be 'file' (the coefficient file's, the plug-in's at speeds it lacks) or "
                           "'plugin' (the plug-in's, with the file's capacity scale), not '" << strTables << "'");
    if (strFile.empty() && strTables == "file")
      THROW_ARGOSEXCEPTION("calibrated battery: the attribute 'coefficients' is required (a battery coefficient file written by epuck2-fit)");
    if (strBehaviour == "argos" || strBehaviour == "argos_compatible")
      m_eBehaviour = mb::Behaviour::argos_compatible;
    else if (strBehaviour == "corrected")
      m_eBehaviour = mb::Behaviour::corrected;
    else
      THROW_ARGOSEXCEPTION("calibrated battery: behaviour must be 'argos' or 'corrected', not '" << strBehaviour << "'");
    std::shared_ptr<const SBatteryFile> pcFile;
    std::string strPath;
    if (!strFile.empty()) {
      ExpandEnvVariables(strFile);
      strPath = epuck2::coefficients::resolve_model_path(strFile, CSimulator::GetInstance().GetExperimentFileName());
      try {
        pcFile = SharedBatteryFile(strPath);
      } catch (const std::exception& ex) {
        THROW_ARGOSEXCEPTION("calibrated battery: " << ex.what());
      }
    }
    /* The discharge model: the XML's, else the file's battery_model (a diagnosis), else Cubic */
    if (strModel == "approx") strModel = "approximated";
    if (!strModel.empty()) {
      if (!mb::parse_model(strModel, m_eModel))
        THROW_ARGOSEXCEPTION("calibrated battery: model must be simple, linear, cubic or approximated, not '" << strModel << "'");
    } else if (pcFile && pcFile->HasModel) {
      m_eModel = pcFile->Model;
    }
    m_sCapacity.k = pcFile ? pcFile->CapacityK : 1.0;
    if (strTables == "plugin") {
      static const mb::Tables& cPlugin = mb::plugin_tables();
      m_pcTables = std::shared_ptr<const mb::Tables>(std::shared_ptr<const mb::Tables>{}, &cPlugin);
    } else {
      m_pcTables = std::shared_ptr<const mb::Tables>(pcFile, &pcFile->Tables);
    }
    /* Say once per file what is used where */
    static std::set<std::string> setSaid;
    const std::string strKey = strPath + "|" + strTables;
    if (setSaid.insert(strKey).second) {
      std::ostringstream os;
      os << "calibrated battery: " << (strPath.empty() ? std::string("no file") : strPath) << ": ";
      if (strTables == "plugin") {
        os << "the plug-in's tables at every speed";
      } else {
        os << "fitted tables at " << Speeds(pcFile->Sources.fitted_speeds) << " cm/s";
        std::vector<int> vecPlugin;
        for (int v = 0; v < static_cast<int>(mb::kSpeedCount); ++v)
          if (std::find(pcFile->Sources.fitted_speeds.begin(), pcFile->Sources.fitted_speeds.end(), v) == pcFile->Sources.fitted_speeds.end())
            vecPlugin.push_back(v);
        if (!vecPlugin.empty()) os << ", the plug-in's at " << Speeds(vecPlugin) << " cm/s";
        if (!pcFile->Sources.fitted_simple) os << "; the Simple model's slopes the plug-in's";
      }
      os << "; model " << mb::to_string(m_eModel);
      if (m_sCapacity.k != 1.0) os << "; capacity scale " << m_sCapacity.k << " (lifetimes x " << m_sCapacity.k << ")";
      LOG << "[INFO] " << os.str() << std::endl;
    }
    /* Cubic tables the plug-in's own arithmetic never empties (Cardano's root clamped at 0 from
       the first tick): a battery that never runs down, said once per file and tables, as
       `epuck2-fit battery` said when it wrote them (lib/models battery.hpp, argos_cubic_stalls) */
    if (m_eBehaviour == mb::Behaviour::argos_compatible && m_eModel == mb::Model::cubic) {
      static std::set<std::string> setWarned;
      if (setWarned.insert(strKey).second) {
        const Real fTick = CPhysicsEngine::GetSimulationClockTick();
        const double fDt = (fTick > 0 ? fTick : 0.1) / (m_sCapacity.k > 0 ? m_sCapacity.k : 1.0);
        const auto vecStalls = mb::argos_cubic_stalls(*m_pcTables, fDt);
        if (!vecStalls.empty()) {
          LOGERR << "[WARNING] calibrated battery: " << (strPath.empty() ? std::string("no file") : strPath) << ": "
                 << mb::argos_cubic_stall_text(vecStalls, fDt) << std::endl;
          LOGERR.Flush();
        }
      }
    }
  }

  void SetBattery(CEPuck2BatteryEquippedEntity* pc_battery) override {
    try {
      CEPuck2BatteryDischargeModel::SetBattery(pc_battery);
      auto* pcComp = dynamic_cast<CComposableEntity*>(&pc_battery->GetRootEntity());
      if (pcComp == nullptr) THROW_ARGOSEXCEPTION("Root entity is not composable");
      m_psAnchor = &pcComp->GetComponent<CEmbodiedEntity>("body").GetOriginAnchor();
      m_cOldPosition = m_cStartPosition = m_psAnchor->Position;
      m_cOldOrientation = m_cStartOrientation = m_psAnchor->Orientation;
    } catch (CARGoSException& ex) {
      THROW_ARGOSEXCEPTION_NESTED("While setting body for battery model \"calibrated\"", ex);
    }
  }

  /* ARGoS's Reset (the Qt "reset" button, a batch driver repeating trials) must start the battery
     again as at Init. The plug-in's battery entity has no Reset: its charge, and every discharge
     model's state, would go on from where the run stopped (a plug-in quirk, docs/argos.md), and
     it never calls this. So the model also restarts itself when the simulation clock goes back
     (operator() below). */
  void Reset() override {
    if (m_bRan) Restart();
    m_bRan = false;
  }

  void operator()() override {
    const UInt32 unClock = CSimulator::GetInstance().GetSpace().GetSimulationClock();
    if (m_bRan && unClock <= m_unLastClock) Restart();
    if (!m_bRan) m_fStartCharge = m_pcBattery->GetAvailableCharge();  // the first tick: nothing spent yet
    m_bRan = true;
    m_unLastClock = unClock;
    if (m_pcBattery->GetAvailableCharge() > 0.0) {
      /* The plug-in's distance: displacement, else the rotation angle times 0.0265f */
      Real fDeltaPos = Distance(m_psAnchor->Position, m_cOldPosition);
      CQuaternion cDeltaOrient = m_cOldOrientation.Inverse() * m_psAnchor->Orientation;
      CRadians cDeltaAngle;
      CVector3 cDeltaAxis;
      cDeltaOrient.ToAngleAxis(cDeltaAngle, cDeltaAxis);
      if (fDeltaPos == 0.0 && cDeltaAngle.GetValue() != 0.0) fDeltaPos = cDeltaAngle.GetValue() * mb::kHalfAxleFloat_m;
      const Real fDeltaT = CPhysicsEngine::GetSimulationClockTick();
      /* capacity_scale: a battery of k times the capacity discharges as the model does with time
         running 1/k as fast (lib/models battery.hpp, CapacityScale); k = 1 is the plain tick */
      const double fK = m_sCapacity.k;
      m_pcBattery->SetAvailableCharge(mb::step(m_eModel, m_eBehaviour, *m_pcTables, m_pcBattery->GetAvailableCharge(),
                                               fK == 1.0 ? fDeltaPos : fDeltaPos / fK,
                                               fK == 1.0 ? fDeltaT : fDeltaT / fK, m_sHints));
      m_cOldPosition = m_psAnchor->Position;
      m_cOldOrientation = m_psAnchor->Orientation;
    }
  }

 private:
  /// The state of the first tick: the start charge, no hints, the pose the body had at Init.
  void Restart() {
    m_pcBattery->SetAvailableCharge(m_fStartCharge);
    m_sHints = mb::corrected::CubicHints{};
    m_cOldPosition = m_cStartPosition;
    m_cOldOrientation = m_cStartOrientation;
  }

  const SAnchor* m_psAnchor = nullptr;
  CVector3 m_cOldPosition, m_cStartPosition;
  CQuaternion m_cOldOrientation, m_cStartOrientation;
  bool m_bRan = false;       ///< operator() has run since Init (or the last restart)
  UInt32 m_unLastClock = 0;  ///< the simulation clock at the last operator()
  Real m_fStartCharge = 1.0;
  mb::Model m_eModel = mb::Model::cubic;
  mb::Behaviour m_eBehaviour = mb::Behaviour::argos_compatible;
  std::shared_ptr<const mb::Tables> m_pcTables;  ///< shared by every robot with the same file
  mb::CapacityScale m_sCapacity;
  mb::corrected::CubicHints m_sHints{};
};

REGISTER_BATTERY_DISCHARGE_MODEL(CEPuck2BatteryDischargeModelCalibrated, "calibrated");

}  // namespace argos
