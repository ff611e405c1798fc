#include "ramtk/calib/robot_calibration_report.h"

#include <cstdio>
#include <string>

#include "ramtk/core/units.h"

namespace ramtk::calib {
namespace {

std::string Fixed(double v, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, v);
  return text;
}

std::vector<std::string> StatsRow(const std::string& what, const ResidualStats& s) {
  return {what, Fixed(s.rms_per_coordinate_mm, 4), Fixed(s.rms_3d_mm, 4), Fixed(s.max_3d_mm, 4),
          s.rms_rotation_deg > 0 ? Fixed(s.rms_rotation_deg, 4) : ""};
}

report::Series Norms(const std::string& label, const std::vector<Vec3>& residuals) {
  report::Series s;
  s.label = label;
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    s.x.push_back(static_cast<double>(i));
    s.y.push_back(residuals[i].norm());
  }
  return s;
}

}  // namespace

report::HtmlReport RobotCalibrationReport(const RobotCalibration& c, const RobotCalibrationSummary& s,
                                          const kinematics::TrackerMeasurements& data) {
  report::HtmlReport html("Robot calibration: " + c.chain.name);
  html.Paragraph(s.BriefReport());
  std::string terms;
  for (const std::string& t : s.terms_kept) terms += (terms.empty() ? "" : ", ") + t;
  html.KeyValues({{"poses", std::to_string(s.num_poses)},
                  {"targets", std::to_string(s.num_targets)},
                  {"6-D rotations used", s.used_rotation ? "yes" : "no"},
                  {"σ weighted by (position mm / rotation deg)",
                   Fixed(s.position_sigma_mm, 4) + " / " + (s.used_rotation ? Fixed(s.rotation_sigma_deg, 5) : "—")},
                  {"unknowns identified / eliminated", std::to_string(s.num_identified) + " / " + std::to_string(s.num_eliminated)},
                  {"condition number (unit columns)", Fixed(s.condition_number, 1)},
                  {"observability index O1 / noise amplification", Fixed(s.observability_index, 5) + " / " +
                                                                     Fixed(s.noise_amplification_index, 5)},
                  {"predicted held-out RMS per coordinate (mm)", Fixed(s.predicted_held_out_mm, 4)},
                  {"terms kept", terms.empty() ? "none" : terms}});
  for (const std::string& w : s.warnings) html.Paragraph("Warning: " + w);

  html.Section("Residuals (mm)");
  html.Table({"", "RMS per coordinate", "3-D RMS", "3-D max", "rotation RMS (deg)"},
             {StatsRow("nominal links, set-up fitted", s.before), StatsRow("calibrated, fit", s.after),
              StatsRow("held-out, links only", s.held_out_geometric), StatsRow("held-out, final model", s.held_out)});
  report::Figure per_pose;
  per_pose.id = "residual_per_pose";
  per_pose.caption = "|measured − predicted| of the first target per pose, in file order: with the nominal links (set-up "
                     "fitted), after the calibration, and predicted by the folds that did not see the pose.";
  report::Panel p;
  p.x_label = "pose (file order)";
  p.y_label = "|residual| (mm)";
  p.series = {Norms("nominal", s.residuals_before), Norms("calibrated", s.residuals_after),
              Norms("held-out", s.residuals_held_out)};
  per_pose.panels.push_back(p);
  html.AddFigure(per_pose);

  report::Figure joints;
  joints.id = "residual_vs_joints";
  joints.caption = "The calibrated residual of each pose against each joint's angle: a trend left here is what the "
                   "model does not hold.";
  for (int j = 0; j < data.num_joints; ++j) {
    report::Panel q;
    q.x_label = "q" + std::to_string(j + 1) + " (deg)";
    q.y_label = "|residual| (mm)";
    report::Series series;
    for (std::size_t i = 0; i < data.poses.size() && i < s.residuals_after.size(); ++i) {
      series.x.push_back(RadToDeg(data.poses[i].q_rad[j]));
      series.y.push_back(s.residuals_after[i].norm());
    }
    q.series.push_back(series);
    joints.panels.push_back(q);
  }
  html.AddFigure(joints);

  report::Cloud3d cloud;
  cloud.title = "measured targets, coloured by the calibrated residual";
  cloud.colour_label = "|residual| (µm)";
  cloud.diverging = false;
  for (std::size_t i = 0; i < data.poses.size() && i < s.residuals_after.size(); ++i) {
    const Vec3& p3 = data.poses[i].targets[0].position_mm;
    cloud.xyz.insert(cloud.xyz.end(), {static_cast<float>(p3.x()), static_cast<float>(p3.y()), static_cast<float>(p3.z())});
    cloud.colour_value.push_back(static_cast<float>(1000.0 * s.residuals_after[i].norm()));
  }
  html.AddCloud("targets_3d", cloud, "Where in the tracker frame the residual is large.");

  html.Section("Unknowns and identifiability");
  std::vector<std::vector<std::string>> rows;
  for (const CalibrationUnknown& u : c.unknowns) {
    if (u.status == "fixed") continue;
    rows.push_back({u.name, u.status, Fixed(u.nominal, 5), Fixed(u.value, 5), u.sigma > 0 ? Fixed(u.sigma, 5) : "",
                    u.unit, u.combination.empty() ? "" : Fixed(u.independence, 8) + "; " + u.combination});
  }
  html.Table({"unknown", "status", "nominal", "value", "σ", "unit", "independence; combination"}, rows);
  return html;
}

}  // namespace ramtk::calib
