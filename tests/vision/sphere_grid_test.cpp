// The RANSAC point grid (vision/sphere/include/ramtk/vision/sphere/detail/sphere_fit_internal.h; its cell keys four points at a time on
// AVX2 lanes, and one by one) against a brute-force listing: every
// neighbourhood holds exactly the active points whose cell is within one cell of the query's on
// each axis, cell by cell in offset order and, within a cell, in the order of the active list.
// The points are laid out as a scan's are (rows of a surface, so consecutive points mostly share
// a cell and the grid is built from runs over several chunks of the active list), with some
// exactly on cell boundaries and some left out of the active list. And the band test of the
// RANSAC scoring (WithinBand) and the split around a candidate (SplitByDistance) against Eigen's
// norm, point by point, with the AVX2 lanes and without.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <random>
#include <vector>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/vision/sphere/detail/sphere_fit_internal.h"

namespace ramtk::vision::sphere_internal {
namespace {

TEST(PointGrid, NeighbourhoodsListTheCellsPointsInActiveOrder) {
  constexpr double kCell = 2.5;  // mm
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  std::vector<Eigen::Vector3f> points;
  // 400 rows of 400 points on a wavy surface, 0.1 mm apart: ~160 k points, three chunks of the
  // 65 536-point runs and revisits of each cell from many rows.
  for (int r = 0; r < 400; ++r)
    for (int c = 0; c < 400; ++c) {
      const double x = 0.1 * c, y = 0.1 * r;
      points.emplace_back(static_cast<float>(x), static_cast<float>(y),
                          static_cast<float>(3.0 * std::sin(0.2 * x) * std::cos(0.15 * y) + jitter(rng)));
    }
  // Points exactly on cell boundaries (multiples of the cell from the origin, the first active
  // point), where a floor of the quotient decides the cell.
  for (int k = -4; k <= 4; ++k)
    points.emplace_back(0.0f, static_cast<float>(k * kCell), static_cast<float>(-k * kCell));
  std::vector<int> active;
  for (int i = 0; i < static_cast<int>(points.size()); ++i)
    if (i % 97 != 5) active.push_back(i);  // a few points left out
  const Eigen::Vector3d origin = points[active.front()].cast<double>();
  auto cell_of = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d g = (p - origin) / kCell;
    return Eigen::Vector3i(static_cast<int>(std::floor(g.x())), static_cast<int>(std::floor(g.y())),
                           static_cast<int>(std::floor(g.z())));
  };
  for (const bool lanes : {false, true}) {  // the cell keys four points at a time on AVX2 lanes, or one by one
    detail::SetAvx2Kernels(lanes);
    PointGrid grid(points, active, kCell);
    std::vector<Eigen::Vector3d> queries;
    for (int k = 0; k < 60; ++k) queries.push_back(points[active[rng() % active.size()]].cast<double>());
    for (int k = points.size() - 9; k < static_cast<int>(points.size()); ++k)
      queries.push_back(points[k].cast<double>());
    queries.emplace_back(1e4, 1e4, 1e4);  // far from every point: empty
    for (const Eigen::Vector3d& q : queries) {
      const Eigen::Vector3i cq = cell_of(q);
      std::vector<int> expected;
      for (int di = -1; di <= 1; ++di)
        for (int dj = -1; dj <= 1; ++dj)
          for (int dk = -1; dk <= 1; ++dk)
            for (int i : active)
              if (cell_of(points[i].cast<double>()) == cq + Eigen::Vector3i(di, dj, dk)) expected.push_back(i);
      const CellNeighbourhood& nb = grid.Neighbourhood(q);
      std::vector<int> got;
      nb.ForEach([&](int i) { got.push_back(i); });
      ASSERT_EQ(got, expected) << "query " << q.transpose();
      ASSERT_EQ(nb.size(), expected.size());
      for (std::size_t k = 0; k < expected.size(); k += 997) EXPECT_EQ(nb[k], expected[k]);
      // Strided, from an offset: every stride-th of the same list.
      std::vector<int> strided;
      nb.ForEachStrided(3, 7, [&](int i) { strided.push_back(i); });
      std::vector<int> want;
      for (std::size_t k = 3; k < expected.size(); k += 7) want.push_back(expected[k]);
      EXPECT_EQ(strided, want);
    }
  }
  detail::SetAvx2Kernels(true);
}

// The points of a neighbourhood within the band, as Eigen's norm puts them, with the lanes and
// without.
void ExpectEigensBand(const std::vector<Eigen::Vector3f>& points, const CellNeighbourhood& nb, std::size_t stride,
                      const Eigen::Vector3d& centre, double radius, double band) {
  std::vector<int> want;
  for (std::size_t k = stride - 1; k < nb.size(); k += stride) {
    const int i = nb[k];
    if (std::abs((points[i].cast<double>() - centre).norm() - radius) <= band) want.push_back(i);
  }
  // SplitByDistance over the same points: within 5 band (near) and within band, as FindSpheres
  // splits the cloud around a candidate.
  std::vector<int> listed, want_near, want_in;
  for (std::size_t k = stride - 1; k < nb.size(); k += stride) {
    const int i = nb[k];
    listed.push_back(i);
    const double d = std::abs((points[i].cast<double>() - centre).norm() - radius);
    if (d <= 5 * band) want_near.push_back(i);
    if (d <= band) want_in.push_back(i);
  }
  for (const bool lanes : {false, true}) {
    detail::SetAvx2Kernels(lanes);
    std::vector<int> near, in_band;
    SplitByDistance(points, listed.data(), static_cast<int>(listed.size()), centre, radius, 5 * band, band, &near,
                    &in_band);
    ASSERT_EQ(near, want_near) << (lanes ? "lanes" : "");
    ASSERT_EQ(in_band, want_in) << (lanes ? "lanes" : "");
    std::vector<int> got;
    ASSERT_EQ(WithinBand(points, nb, stride - 1, stride, centre, radius, band, &got), static_cast<int>(want.size()));
    ASSERT_EQ(got, want) << "radius " << radius << ", stride " << stride << (lanes ? ", lanes" : "");
    ASSERT_EQ(WithinBand(points, nb, stride - 1, stride, centre, radius, band, nullptr), static_cast<int>(want.size()));
  }
  detail::SetAvx2Kernels(true);
}

TEST(WithinBand, CountsAndListsThePointsEigensNormPutsInTheBand) {
  // A centre of full 53-bit coordinates: the squares of the differences round (with a centre of few
  // bits they are exact and every order of the sum agrees).
  const Eigen::Vector3d centre(3.25 + 1.0 / 3, -1.5 + 1.0 / 7, 702.125 + 1.0 / 11);
  const double radius = 19.05, band = 0.01;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> dir(0.0, 1.0);
  std::uniform_real_distribution<double> offset(-0.05, 0.05);
  auto on_shell = [&](double off) -> Eigen::Vector3f {  // evaluated here (u is local)
    const Eigen::Vector3d u(dir(rng), dir(rng), dir(rng));
    return (centre + (radius + off) * u.normalized()).cast<float>();
  };
  // A ball's points around the band, in 27-cell neighbourhoods of ragged sizes (small cells),
  // all of them and every third.
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 30000; ++i) points.push_back(on_shell(offset(rng)));
  std::vector<int> active(points.size());
  for (std::size_t i = 0; i < active.size(); ++i) active[i] = static_cast<int>(i);
  PointGrid grid(points, active, 4.0);
  for (int q = 0; q < 40; ++q)
    for (const std::size_t stride : {std::size_t{1}, std::size_t{3}})
      ExpectEigensBand(points, grid.Neighbourhood(points[(q * 7919) % points.size()].cast<double>()), stride, centre,
                       radius, band);
  // The band's very edge: for each of 300 points the radius that puts it at `band` from the
  // sphere as Eigen computes its distance, so that the last bit of the norm decides (a sum of the
  // squares in another order flips some of them).
  std::vector<Eigen::Vector3f> few(points.begin(), points.begin() + 300);
  std::vector<int> all(few.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  PointGrid one_cell(few, all, 1000.0);
  const CellNeighbourhood& nb = one_cell.Neighbourhood(centre);
  ASSERT_EQ(nb.size(), few.size());
  for (const Eigen::Vector3f& p : few)
    ExpectEigensBand(few, nb, 1, centre, (p.cast<double>() - centre).norm() - band, band);
}

}  // namespace
}  // namespace ramtk::vision::sphere_internal
