// The RANSAC point grid (vision/src/sphere_fit_internal.h) against a brute-force listing: every
// neighbourhood holds exactly the active points whose cell is within one cell of the query's on
// each axis, cell by cell in offset order and, within a cell, in the order of the active list.
// The points are laid out as a scan's are (rows of a surface, so consecutive points mostly share
// a cell and the grid is built from runs over several chunks of the active list), with some
// exactly on cell boundaries and some left out of the active list.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <random>
#include <vector>

#include "../../vision/src/sphere_fit_internal.h"

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
  PointGrid grid(points, active, kCell);
  std::vector<Eigen::Vector3d> queries;
  for (int k = 0; k < 60; ++k) queries.push_back(points[active[rng() % active.size()]].cast<double>());
  for (int k = points.size() - 9; k < static_cast<int>(points.size()); ++k) queries.push_back(points[k].cast<double>());
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

}  // namespace
}  // namespace ramtk::vision::sphere_internal
