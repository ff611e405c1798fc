#include "ramtk/diagnose/engine/catalogue.h"

namespace ramtk::diagnose {

const std::vector<EffectInfo>& EffectCatalogue() {
  static const std::vector<EffectInfo> catalogue = {
      {"projector_nonlinearity", DataKind::kFringe,
       "projector response is not linear (gamma): phase ripple at N× the fringe frequency"},
      {"phase_shift_error", DataKind::kFringe, "the projected phase steps differ from 2π/N"},
      {"intensity_drift", DataKind::kFringe, "illumination or exposure changes from frame to frame"},
      {"saturation", DataKind::kFringe, "the camera clips bright samples"},
      {"defocus", DataKind::kFringe, "projector or camera blur lowers the modulation of fine patterns"},
      {"ambient_light", DataKind::kFringe, "light not from the projector raises the background"},
      {"lens_distortion_unmodelled", DataKind::kFringe, "the calibration misses part of the lens distortion"},
      {"camera_defocus", DataKind::kFringe, "the camera blurs the image (mixes neighbouring pixels of different albedo)"},
      {"signal_dependent_noise", DataKind::kFringe,
       "noise variance grows faster with intensity than read + photon shot noise (a + b·I) allows"},
      {"soft_knee_response", DataKind::kFringe, "bright samples are compressed smoothly below full scale"},
      {"joint_offset", DataKind::kRobot, "a joint's zero differs from the model"},
      {"link_length_error", DataKind::kRobot, "a link length differs from the model"},
      {"thermal_length_drift", DataKind::kRobot, "link lengths grow with temperature"},
      {"thermal_angle_drift", DataKind::kRobot, "joint angles and link twists drift with temperature"},
      {"joint_compliance", DataKind::kRobot, "joints deflect under gravity load"},
      {"sensor_frame_drift", DataKind::kRobot, "the fixed sensor moves relative to the robot base"},
      {"tool_offset_change", DataKind::kRobot, "the ball moved on the flange"},
      {"joint_cyclic_error", DataKind::kRobot, "a joint's encoder or gear has an error cyclic in its angle (q, 2q)"},
      {"backlash", DataKind::kRobot, "a joint's position depends on the direction it was approached from"},
      {"temperature_driven_drift", DataKind::kRobot, "the residual follows a measured temperature column"},
      {"geometric", DataKind::kRobot, "the static kinematic parameters differ from the model (a full calibration)"},
      {"axis_misalignment", DataKind::kRobot, "a joint axis is twisted against the model (static α, or β on parallel axes)"},
      {"beam_non_perpendicular", DataKind::kLaser, "the two beams are not at 90°"},
      {"beam_offset", DataKind::kLaser, "the beams do not intersect (offset along the tool axis)"},
      {"beam_width", DataKind::kLaser, "the beams have a finite width that shifts the break instants"},
      {"trigger_latency", DataKind::kLaser, "the receiver reports breaks late"},
      {"speed_variation", DataKind::kLaser, "the robot's speed differs from the programmed one"},
      {"sensor_plane_tilt", DataKind::kLaser, "the beam plane is tilted against the motion plane"},
      {"tool_axis_rotation", DataKind::kLaser, "the tool axis is rotated against the flange axis"},
  };
  return catalogue;
}

std::vector<EffectInfo> EffectsOf(DataKind kind) {
  std::vector<EffectInfo> out;
  for (const EffectInfo& e : EffectCatalogue())
    if (e.kind == kind) out.push_back(e);
  return out;
}

bool IsKnownCause(const std::string& name) {
  if (name == kNoEffect || name == kUnexplained || name == kAmbiguous || name == kNotObservable || name == kImplausible) {
    return true;
  }
  for (const EffectInfo& e : EffectCatalogue())
    if (name == e.name) return true;
  return false;
}

}  // namespace ramtk::diagnose
