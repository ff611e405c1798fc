// The "Sphere result" JSON of docs/formats.md.

#include <nlohmann/json.hpp>

#include "ramtk/core/file_io.h"
#include "ramtk/vision/sphere/sphere_fit.h"

namespace ramtk::vision {
namespace {

nlohmann::json Vec(const Eigen::Vector3d& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

}  // namespace

std::string SphereFitToJson(const SphereFitSummary& summary, const std::string& frame, int indent) {
  nlohmann::json j;
  j["format"] = "ramtk-sphere-fit";
  j["version"] = 1;
  j["frame"] = frame;
  j["units"] = "mm";
  j["termination"] = summary.message;
  j["no_sphere_reason"] = summary.no_sphere_reason;
  j["input_points"] = summary.input_points;
  j["unassigned_points"] = summary.unassigned_points;
  j["inlier_threshold_mm"] = summary.inlier_threshold_mm;
  j["spheres"] = nlohmann::json::array();
  for (const SphereResult& s : summary.spheres) {
    nlohmann::json o;
    o["centre_mm"] = Vec(s.centre_mm);
    o["centre_sigma_mm"] = Vec(s.CentreSigma());
    nlohmann::json cov = nlohmann::json::array();
    for (int r = 0; r < 3; ++r) cov.push_back(Vec(s.centre_covariance_mm2.row(r).transpose()));
    o["centre_covariance_mm2"] = cov;
    o["radius_mm"] = s.radius_mm;
    o["radius_sigma_mm"] = s.radius_sigma_mm;
    o["rms_mm"] = s.rms_mm;
    o["worst_mm"] = s.worst_mm;
    o["num_points"] = s.num_points;
    o["num_outliers"] = s.num_outliers;
    o["num_grazing"] = s.num_grazing;
    o["correlation_factor"] = s.correlation_factor;
    o["crlb_centre_sigma_mm"] = Vec(s.crlb_centre_sigma_mm);
    o["crlb_radius_sigma_mm"] = s.crlb_radius_sigma_mm;
    o["variance_factor"] = s.variance_factor;
    o["solver_iterations"] = s.solver_iterations;
    o["ransac_iterations"] = s.ransac_iterations;
    j["spheres"].push_back(o);
  }
  if (summary.spheres.size() >= 2) {
    nlohmann::json d = nlohmann::json::array();
    for (size_t a = 0; a < summary.spheres.size(); ++a)
      for (size_t b = a + 1; b < summary.spheres.size(); ++b) {
        const CentreDistance cd = ComputeCentreDistance(summary.spheres[a], summary.spheres[b]);
        d.push_back({{"a", a}, {"b", b}, {"distance_mm", cd.distance_mm}, {"sigma_mm", cd.sigma_mm}});
      }
    j["centre_distances"] = d;
  }
  return j.dump(indent) + "\n";
}

void WriteSphereFitJson(const std::string& path, const SphereFitSummary& summary, const std::string& frame) {
  WriteFileAtomically(path, SphereFitToJson(summary, frame));
}

}  // namespace ramtk::vision
