// Accuracy sweep of the sphere fit against the synthetic truth: for several point-noise levels
// (sigma along the sight line from sigma_max/6 facing the sensor to sigma_max at the grazing
// limit), over --seeds noise seeds: centre error RMS (3-D), radius error RMS, and the ratio of the
// predicted centre sigma to the observed scatter per axis; ramtk with free radius, known radius,
// and sigmas read as isotropic, and PCL's SACSegmentation on the same clouds.
//   vision_sphere_sweep [--seeds N] [--quick] [--csv FILE]
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include "ramtk/vision/sphere/sphere_fit.h"
#include "sphere_pcl_peer.h"
#include "sphere_synth.h"

using namespace ramtk::vision;

namespace {

struct Accumulator {
  int n = 0, failed = 0;
  double centre2 = 0, radius2 = 0;
  Eigen::Vector3d observed2 = Eigen::Vector3d::Zero(), predicted2 = Eigen::Vector3d::Zero();
  void Add(const Eigen::Vector3d& centre, double radius, const Eigen::Matrix3d& cov, const test::CapScene& truth) {
    const Eigen::Vector3d e = centre - truth.centre;
    ++n;
    centre2 += e.squaredNorm();
    radius2 += (radius - truth.radius) * (radius - truth.radius);
    observed2 += e.cwiseAbs2();
    predicted2 += cov.diagonal();
  }
  double CentreRmsUm() const { return 1e3 * std::sqrt(centre2 / n); }
  double RadiusRmsUm() const { return 1e3 * std::sqrt(radius2 / n); }
  Eigen::Vector3d Ratio() const { return (predicted2.array() / observed2.array()).sqrt(); }
};

}  // namespace

int main(int argc, char** argv) {
  int seeds = 50;
  bool quick = false;
  std::string csv_path;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--seeds") && i + 1 < argc)
      seeds = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--quick"))
      quick = true;
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc)
      csv_path = argv[++i];
    else {
      std::fprintf(stderr, "usage: %s [--seeds N] [--quick] [--csv FILE]\n", argv[0]);
      return 2;
    }
  }
  const std::vector<double> levels = quick ? std::vector<double>{0.03} : std::vector<double>{0.01, 0.02, 0.03, 0.06};
  const char* modes[] = {"free", "known_radius", "isotropic_weights", "pcl"};
  std::string csv = "sigma_max_um,method,seeds,failed,centre_err_rms_um,radius_err_rms_um,ratio_x,ratio_y,ratio_z\n";
  std::printf(
      "| sigma max (um) | method | centre err RMS (um) | radius err RMS (um) | predicted/observed sigma x, y, z |\n");
  std::printf("|---|---|---|---|---|\n");
  for (double level : levels) {
    test::CapScene scene;
    scene.sigma_max_mm = level;
    scene.sigma_min_mm = level / 6;
    Accumulator acc[4];
    for (int k = 0; k < seeds; ++k) {
      const test::SynthCloud cloud = test::MakeCapCloud(scene, 10000 + static_cast<uint64_t>(k));
      for (int m = 0; m < 3; ++m) {
        SphereFitOptions o;
        o.radius_mm = 19.05;
        o.seed = static_cast<uint64_t>(k) + 1;
        o.viewpoint_mm = cloud.viewpoint;
        o.noise_model = m == 2 ? PointNoiseModel::kIsotropic : PointNoiseModel::kAlongLineOfSight;
        o.fix_radius = m == 1;
        const SphereFitSummary s = FindSpheres(cloud.points, cloud.sigma, o);
        if (s.spheres.empty()) {
          ++acc[m].failed;
          continue;
        }
        acc[m].Add(s.spheres[0].centre_mm, s.spheres[0].radius_mm, s.spheres[0].centre_covariance_mm2, scene);
      }
      // PCL: same radius window, band 0.1 mm or 4 x sigma_max, whichever is larger.
      const test::PclSphere p = test::PclFitSphere(test::ToPcl(cloud.points), std::max(0.1, 4 * level), 17.05, 21.05);
      if (p.found)
        acc[3].Add(p.centre, p.radius, Eigen::Matrix3d::Constant(NAN), scene);
      else
        ++acc[3].failed;
    }
    for (int m = 0; m < 4; ++m) {
      const Eigen::Vector3d r = acc[m].Ratio();
      char line[512];
      std::snprintf(line, sizeof(line), "%.0f,%s,%d,%d,%.3f,%.3f,%.3f,%.3f,%.3f\n", level * 1e3, modes[m], seeds,
                    acc[m].failed, acc[m].CentreRmsUm(), acc[m].RadiusRmsUm(), r.x(), r.y(), r.z());
      csv += line;
      if (m == 3)
        std::printf("| %.0f | %s | %.3f | %.3f | — |\n", level * 1e3, modes[m], acc[m].CentreRmsUm(),
                    acc[m].RadiusRmsUm());
      else
        std::printf("| %.0f | %s | %.3f | %.3f | %.2f, %.2f, %.2f |\n", level * 1e3, modes[m], acc[m].CentreRmsUm(),
                    m == 1 ? 0.0 : acc[m].RadiusRmsUm(), r.x(), r.y(), r.z());
      if (acc[m].failed > 0) std::printf("  (%d of %d seeds found no sphere)\n", acc[m].failed, seeds);
    }
  }
  if (!csv_path.empty()) std::ofstream(csv_path) << csv;
  return 0;
}
