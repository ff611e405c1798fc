// The match's searched pixels of a row and its valid cells (vision/stereo/include/ramtk/vision/stereo/detail/stereo_search_list.h)
// against the rules written out pixel by pixel: mask set and coordinate finite (valid), sigma <=
// the limit compared in double (else noisy), reach set (else unreachable). With the AVX2 lanes
// and without, on rows of odd widths with NaN and infinite coordinates, NaN sigmas, sigmas one
// float step either side of the limit, and runs of masked pixels.
#include "ramtk/vision/stereo/detail/stereo_search_list.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "ramtk/vision/kernels/avx2.h"

namespace ramtk::vision::detail {
namespace {

TEST(SearchList, ListsAndCountsAsThePixelRule) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> pick(0, 99);
  const double max_sigma = 0.1234567890123;  // no float equals it: the float steps around it decide
  const float below = static_cast<float>(max_sigma) <= max_sigma ? static_cast<float>(max_sigma)
                                                                 : std::nextafter(static_cast<float>(max_sigma), 0.0f);
  const float above = std::nextafter(below, 1.0f);
  ASSERT_LE(static_cast<double>(below), max_sigma);
  ASSERT_GT(static_cast<double>(above), max_sigma);
  long listed = 0;
  for (const int width : {1, 7, 8, 9, 64, 1283}) {
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<uchar> mask(width), reach(width);
      std::vector<float> coord(width), sigma(width);
      for (int x = 0; x < width; ++x) {
        const bool masked_run = (x / 16) % 5 == 3;  // every fifth run of 16 masked whole
        mask[x] = masked_run || pick(rng) < 10 ? 0 : static_cast<uchar>(1 + pick(rng));
        const int c = pick(rng);
        coord[x] = c < 5   ? std::numeric_limits<float>::quiet_NaN()
                   : c < 8 ? (c % 2 ? 1 : -1) * std::numeric_limits<float>::infinity()
                           : 100.0f * pick(rng);
        const int s = pick(rng);
        sigma[x] = s < 5 ? std::numeric_limits<float>::quiet_NaN() : s < 30 ? below : s < 55 ? above : 0.01f * s;
        reach[x] = pick(rng) < 15 ? 0 : 1;
      }
      for (const bool with_reach : {false, true}) {
        std::vector<int> want;
        SearchCounts want_counts;
        for (int x = 0; x < width; ++x) {
          if (!mask[x] || !std::isfinite(coord[x])) continue;
          ++want_counts.valid;
          if (!(static_cast<double>(sigma[x]) <= max_sigma))
            ++want_counts.noisy;
          else if (with_reach && !reach[x])
            ++want_counts.unreachable;
          else
            want.push_back(x);
        }
        for (const bool lanes : {false, true}) {
          SetAvx2Kernels(lanes);
          std::vector<int> xs(width + 8, -1);
          SearchCounts counts;
          const int n = ListSearchedPixels(mask.data(), coord.data(), sigma.data(), with_reach ? reach.data() : nullptr,
                                           width, max_sigma, xs.data(), &counts);
          xs.resize(n);
          EXPECT_EQ(xs, want) << "width " << width << (lanes ? ", lanes" : "");
          EXPECT_EQ(counts.valid, want_counts.valid);
          EXPECT_EQ(counts.noisy, want_counts.noisy);
          EXPECT_EQ(counts.unreachable, want_counts.unreachable);
        }
        listed += static_cast<long>(want.size());
      }
    }
  }
  SetAvx2Kernels(true);
  EXPECT_GT(listed, 5000);  // the lists are not all empty
}

// The cells the match interpolates (Pass::cell_ok) against the rule written out cell by cell:
// four finite corners whose float extremes differ by at most max_span in double. Spans at
// max_span exactly and one float step above, NaN and infinite corners, odd widths; with the
// AVX2 lanes and without.
TEST(SearchList, CellRowAsTheCellRule) {
  std::mt19937 rng(8);
  std::uniform_int_distribution<int> pick(0, 99);
  std::uniform_real_distribution<float> base(100.0f, 900.0f);
  const float step = 0.25f;
  const double max_span = 3.0 * step;  // a corner step of 0.75 (3 steps) is at the limit
  long cells = 0, ok_cells = 0;
  for (const int n : {1, 7, 8, 9, 63, 1281}) {
    std::vector<float> r0(n + 1), r1(n + 1);
    for (int x = 0; x <= n; ++x) {
      const float b = 512.0f;  // a power of two: the steps below are exact
      const int kind = pick(rng);
      r0[x] = kind < 3   ? std::numeric_limits<float>::quiet_NaN()
              : kind < 5 ? std::numeric_limits<float>::infinity()
                         : b;
      const int jump = pick(rng);
      r1[x] = jump < 75 ? r0[x] + 3 * step : jump < 90 ? std::nextafter(r0[x] + 3 * step, 1e9f) : base(rng);
    }
    std::vector<uchar> want(n);
    for (int x = 0; x < n; ++x) {
      const float c[4] = {r0[x], r0[x + 1], r1[x], r1[x + 1]};
      bool finite = true;
      for (const float v : c) finite = finite && std::isfinite(v);
      const float hi = std::max(std::max(c[0], c[1]), std::max(c[2], c[3]));
      const float lo = std::min(std::min(c[0], c[1]), std::min(c[2], c[3]));
      want[x] = finite && static_cast<double>(hi) - static_cast<double>(lo) <= max_span;
      ++cells;
      ok_cells += want[x];
    }
    for (const bool lanes : {false, true}) {
      SetAvx2Kernels(lanes);
      std::vector<uchar> got(n, 7);
      CellRow(r0.data(), r1.data(), n, max_span, got.data());
      EXPECT_EQ(got, want) << "n " << n << (lanes ? ", lanes" : "");
    }
  }
  SetAvx2Kernels(true);
  EXPECT_GT(ok_cells, cells / 10);
  EXPECT_LT(ok_cells, cells);
}

}  // namespace
}  // namespace ramtk::vision::detail
