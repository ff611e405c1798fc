#pragma once
// The peer: PCL's RANSAC sphere fit as a PCL user runs it (pcl::SACSegmentation, SACMODEL_SPHERE,
// SAC_RANSAC, radius limits, optimized coefficients on: a Levenberg-Marquardt geometric refit on
// the RANSAC inliers). Used by the tests and benchmarks that compare ramtk with it.

#include <pcl/ModelCoefficients.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <Eigen/Core>
#include <vector>

namespace ramtk::vision::test {

struct PclSphere {
  bool found = false;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 0;
  int inliers = 0;
};

inline pcl::PointCloud<pcl::PointXYZ>::Ptr ToPcl(const std::vector<Eigen::Vector3f>& points) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->reserve(points.size());
  for (const auto& p : points) cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  return cloud;
}

inline PclSphere PclFitSphere(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud, double threshold_mm, double radius_lo,
                              double radius_hi, int max_iterations = 10000) {
  pcl::SACSegmentation<pcl::PointXYZ> seg;
  seg.setOptimizeCoefficients(true);
  seg.setModelType(pcl::SACMODEL_SPHERE);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setDistanceThreshold(threshold_mm);
  seg.setRadiusLimits(radius_lo, radius_hi);
  seg.setMaxIterations(max_iterations);
  seg.setProbability(0.9999);
  seg.setInputCloud(cloud);
  pcl::PointIndices inliers;
  pcl::ModelCoefficients coefficients;
  seg.segment(inliers, coefficients);
  PclSphere out;
  if (coefficients.values.size() != 4 || inliers.indices.empty()) return out;
  out.found = true;
  out.centre = Eigen::Vector3d(coefficients.values[0], coefficients.values[1], coefficients.values[2]);
  out.radius = coefficients.values[3];
  out.inliers = static_cast<int>(inliers.indices.size());
  return out;
}

}  // namespace ramtk::vision::test
