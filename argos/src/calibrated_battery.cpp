// The `calibrated` battery discharge model: the E-Puck2 plug-in's four models (simple, linear,
// cubic, approximated) with tables fitted by epuck2-fit (battery.json), through the plug-in's
// discharge-model factory, the arithmetic being epuck2::models::battery::step.
//
//   <epuck2 id="ep0">
//     <epuck2_battery discharge_model="calibrated" coefficients="battery.json"
//                     model="cubic" behaviour="argos" start_charge="1.0"/>
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

#include <memory>

#include <epuck2/models/battery.hpp>

#include "coefficient_file.hpp"

namespace argos {

namespace mb = epuck2::models::battery;

class CEPuck2BatteryDischargeModelCalibrated : public CEPuck2BatteryDischargeModel {
 public:
  void Init(TConfigurationNode& t_tree) override {
    std::string strFile, strModel = "cubic", strBehaviour = "argos";
    GetNodeAttributeOrDefault(t_tree, "coefficients", strFile, strFile);
    GetNodeAttributeOrDefault(t_tree, "model", strModel, strModel);
    GetNodeAttributeOrDefault(t_tree, "behaviour", strBehaviour, strBehaviour);
    if (strFile.empty())
      THROW_ARGOSEXCEPTION("calibrated battery: the attribute 'coefficients' is required (a battery coefficient file written by epuck2-fit)");
    if (strModel == "approx") strModel = "approximated";
    if (!mb::parse_model(strModel, m_eModel))
      THROW_ARGOSEXCEPTION("calibrated battery: model must be simple, linear, cubic or approximated, not '" << strModel << "'");
    if (strBehaviour == "argos" || strBehaviour == "argos_compatible")
      m_eBehaviour = mb::Behaviour::argos_compatible;
    else if (strBehaviour == "corrected")
      m_eBehaviour = mb::Behaviour::corrected;
    else
      THROW_ARGOSEXCEPTION("calibrated battery: behaviour must be 'argos' or 'corrected', not '" << strBehaviour << "'");
    ExpandEnvVariables(strFile);
    const std::string strPath =
        epuck2::argos_plugin::resolve_coefficient_path(strFile, CSimulator::GetInstance().GetExperimentFileName());
    try {
      m_pcTables = epuck2::argos_plugin::shared_battery_tables(strPath);
    } catch (const std::exception& ex) {
      THROW_ARGOSEXCEPTION("calibrated battery: " << ex.what());
    }
  }

  void SetBattery(CEPuck2BatteryEquippedEntity* pc_battery) override {
    try {
      CEPuck2BatteryDischargeModel::SetBattery(pc_battery);
      auto* pcComp = dynamic_cast<CComposableEntity*>(&pc_battery->GetRootEntity());
      if (pcComp == nullptr) THROW_ARGOSEXCEPTION("Root entity is not composable");
      m_psAnchor = &pcComp->GetComponent<CEmbodiedEntity>("body").GetOriginAnchor();
      m_cOldPosition = m_psAnchor->Position;
      m_cOldOrientation = m_psAnchor->Orientation;
    } catch (CARGoSException& ex) {
      THROW_ARGOSEXCEPTION_NESTED("While setting body for battery model \"calibrated\"", ex);
    }
  }

  void Reset() override {
    m_sHints = mb::corrected::CubicHints{};
    if (m_psAnchor) {
      m_cOldPosition = m_psAnchor->Position;
      m_cOldOrientation = m_psAnchor->Orientation;
    }
  }

  void operator()() override {
    if (m_pcBattery->GetAvailableCharge() > 0.0) {
      /* The plug-in's distance: displacement, else the rotation angle times 0.0265f */
      Real fDeltaPos = Distance(m_psAnchor->Position, m_cOldPosition);
      CQuaternion cDeltaOrient = m_cOldOrientation.Inverse() * m_psAnchor->Orientation;
      CRadians cDeltaAngle;
      CVector3 cDeltaAxis;
      cDeltaOrient.ToAngleAxis(cDeltaAngle, cDeltaAxis);
      if (fDeltaPos == 0.0 && cDeltaAngle.GetValue() != 0.0) fDeltaPos = cDeltaAngle.GetValue() * mb::kHalfAxleFloat_m;
      const Real fDeltaT = CPhysicsEngine::GetSimulationClockTick();
      m_pcBattery->SetAvailableCharge(
          mb::step(m_eModel, m_eBehaviour, *m_pcTables, m_pcBattery->GetAvailableCharge(), fDeltaPos, fDeltaT, m_sHints));
      m_cOldPosition = m_psAnchor->Position;
      m_cOldOrientation = m_psAnchor->Orientation;
    }
  }

 private:
  const SAnchor* m_psAnchor = nullptr;
  CVector3 m_cOldPosition;
  CQuaternion m_cOldOrientation;
  mb::Model m_eModel = mb::Model::cubic;
  mb::Behaviour m_eBehaviour = mb::Behaviour::argos_compatible;
  std::shared_ptr<const mb::Tables> m_pcTables;  ///< shared by every robot with the same file
  mb::corrected::CubicHints m_sHints{};
};

REGISTER_BATTERY_DISCHARGE_MODEL(CEPuck2BatteryDischargeModelCalibrated, "calibrated");

}  // namespace argos
