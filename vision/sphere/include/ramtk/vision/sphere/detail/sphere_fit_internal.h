#pragma once
// Internals of FindSpheres shared by sphere_fit*.cpp (not installed).

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "ramtk/vision/sphere/sphere_fit.h"

namespace ramtk::vision::sphere_internal {

// f(k) for k in [0, n), over parallel ranges when there are enough (a ball's 40 k points); each
// call must touch only its own k's outputs.
template <class F>
void ForEachIndex(std::size_t n, F f) {
  constexpr std::size_t kGrain = 4096;
  if (n < 2 * kGrain) {
    for (std::size_t k = 0; k < n; ++k) f(k);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t k = r.begin(); k < r.end(); ++k) f(k);
  });
}

// Points hashed into cubic cells of edge `cell_mm`; the 27-cell neighbourhood of a cell holds
// every point within cell_mm of any point of that cell.
// The point indices in the 27 cells around one grid cell, in a fixed order (cells by offset,
// each cell's points in insertion order), as views of the grid's cells: no copy, so a cloud of
// millions of points does not hold each index 27 times (400 MB on a thesis frame).
class CellNeighbourhood {
 public:
  std::size_t size() const { return size_; }
  // The k-th index (k < size()).
  int operator[](std::size_t k) const {
    int c = 0;
    while (k >= start_[c + 1]) ++c;
    return cells_[c][k - start_[c]];
  }
  // Calls f(index) for the elements k = first, first + stride, ... (stride >= 1).
  template <class F>
  void ForEachStrided(std::size_t first, std::size_t stride, F&& f) const {
    std::size_t k = first;
    for (int c = 0; c < count_; ++c) {
      const int* v = cells_[c];
      for (; k < start_[c + 1]; k += stride) f(v[k - start_[c]]);
    }
  }
  template <class F>
  void ForEach(F&& f) const {
    ForEachStrided(0, 1, f);
  }
  // Calls f(indices, n) for each cell's run of indices, in order.
  template <class F>
  void ForEachRun(F&& f) const {
    for (int c = 0; c < count_; ++c) f(cells_[c], start_[c + 1] - start_[c]);
  }

 private:
  friend class PointGrid;
  std::array<const int*, 27> cells_{};
  std::array<std::size_t, 28> start_{};
  int count_ = 0;
  std::size_t size_ = 0;
};

class PointGrid {
 public:
  PointGrid(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& active, double cell_mm);
  // Indices (into the point array) in the 27 cells around the cell of `x`. Cached per cell
  // (the view, not the indices); valid while the grid lives.
  const CellNeighbourhood& Neighbourhood(const Eigen::Vector3d& x);

 private:
  int64_t Key(const Eigen::Vector3d& x) const;
  static int64_t Pack(int64_t i, int64_t j, int64_t k);
  // A cell's points: index_[begin, begin + size).
  struct Span {
    std::size_t begin = 0, size = 0;
  };
  double cell_;
  Eigen::Vector3d origin_;
  std::vector<int> index_;  // the active indices grouped by cell, each cell's in active order
  std::unordered_map<int64_t, Span> cells_;
  std::unordered_map<int64_t, CellNeighbourhood> cache_;
};

struct Candidate {
  bool found = false;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 0;
  int inliers = 0;            // points of the neighbourhood within the band
  int iterations = 0;         // samples drawn
  int radius_ok_samples = 0;  // samples whose sphere passed the radius gate
  std::string reason;         // why none was found
};

// The points of `pool` k = first, first + stride, ... (stride >= 1) within `band` of the sphere:
// |‖p - c‖ - R| <= band with Eigen's norm of the point's double difference from the centre. Their
// count, and with `out` their indices in pool order (cleared first). On CPUs with AVX2 four
// points at a time, bit for bit as Eigen (tests/vision/sphere_grid_test.cpp).
int WithinBand(const std::vector<Eigen::Vector3f>& points, const CellNeighbourhood& pool, std::size_t first,
               std::size_t stride, const Eigen::Vector3d& centre, double radius, double band, std::vector<int>* out);

// Of the points indices[0, n): those within `outer` of the sphere into `near` and those within
// `inner` into `in_band` (appended, in order), the distance as WithinBand's (on AVX2 lanes where
// available, bit for bit as Eigen).
void SplitByDistance(const std::vector<Eigen::Vector3f>& points, const int* indices, int n,
                     const Eigen::Vector3d& centre, double radius, double outer, double inner, std::vector<int>* near,
                     std::vector<int>* in_band);

// RANSAC over the `active` points: 4-point samples from a neighbourhood, radius gate, LO step.
Candidate FindCandidate(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& active, double band_mm,
                        double radius_lo, double radius_hi, const SphereFitOptions& options, std::mt19937_64& rng);

// Least-squares algebraic (Kasa) sphere through the indexed points; false if degenerate.
bool FitAlgebraic(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& indices, Eigen::Vector3d* centre,
                  double* radius);

struct GeometricFit {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 0;
  int iterations = 0;
  double initial_cost = 0, final_cost = 0;
  bool converged = false;
};

// Ceres fit of sum rho((|p_i - c| - R) / sigma_i) over `indices`; loss scale in units of the
// normalised residual (ignored for SphereLoss::kNone). sigma indexed like points (read at
// `indices` only). `precise`: run to rounding level, else stop at a relative cost change of 1e-7.
GeometricFit FitGeometric(const std::vector<Eigen::Vector3f>& points, const double* sigma,
                          const std::vector<int>& indices, const Eigen::Vector3d& centre0, double radius0,
                          bool fix_radius, SphereLoss loss, double loss_scale, int max_iterations, bool precise);

// Ceres fit of sum ((|p_i - v| - t_i) / sigma_i)^2 over `indices`, t_i the distance from the
// viewpoint v along the ray through p_i to its first intersection with the sphere (the nearest
// point of the ray to the centre when the ray misses it). No robust loss; runs to rounding level.
GeometricFit FitAlongRay(const std::vector<Eigen::Vector3f>& points, const double* sigma,
                         const std::vector<int>& indices, const Eigen::Vector3d& viewpoint,
                         const Eigen::Vector3d& centre0, double radius0, bool fix_radius, int max_iterations);

// Residual (in units of sigma) and its gradient with respect to (centre, radius) of FitAlongRay's
// model for one point.
double AlongRayResidual(const Eigen::Vector3d& p, double sigma, const Eigen::Vector3d& viewpoint,
                        const Eigen::Vector3d& centre, double radius, Eigen::Vector4d* gradient);

}  // namespace ramtk::vision::sphere_internal
