// Order statistics by histogram (vision/kernels/include/ramtk/vision/kernels/rank_select.h) against std::nth_element on the
// gathered values: random values over many octaves, ties, masks, NaN pixels, both ranks in one bin;
// each with the AVX2 lanes and without.
#include "ramtk/vision/kernels/rank_select.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

#include "ramtk/vision/kernels/avx2.h"

namespace {

using ramtk::vision::detail::UpperMedian;
using ramtk::vision::detail::ValuesAtRanks;

float NthOf(std::vector<float> v, std::size_t k) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

using ramtk::vision::detail::SetAvx2Kernels;

TEST(RankSelect, MaskedMapAsNthElement) {
  std::mt19937 rng(5);
  std::lognormal_distribution<float> value(2.0f, 2.0f);  // ~1e-3 .. 1e4: many exponents
  std::uniform_int_distribution<int> coin(0, 3);
  cv::Mat values(123, 457, CV_32F), mask(values.size(), CV_8U);
  std::vector<float> gathered;
  for (int y = 0; y < values.rows; ++y)
    for (int x = 0; x < values.cols; ++x) {
      // Every 7th value repeated: ties inside a bin.
      values.at<float>(y, x) = (x % 7 == 0) ? 55.75f : value(rng);
      // Rows 40-59 and the first 100 columns masked whole: runs of masked values skipped at once.
      mask.at<uchar>(y, x) = (coin(rng) && !(y >= 40 && y < 60) && x >= 100) ? 255 : 0;
      if (mask.at<uchar>(y, x)) gathered.push_back(values.at<float>(y, x));
    }
  const std::size_t n = gathered.size();
  const std::vector<std::size_t> ranks{0, n / 2, n - 1 - n / 2, n / 3, n - 1, n / 2 + 1};
  for (const bool lanes : {false, true}) {
    SetAvx2Kernels(lanes);
    const std::vector<float> got = ValuesAtRanks(values, mask, ranks);
    ASSERT_EQ(got.size(), ranks.size());
    for (std::size_t i = 0; i < ranks.size(); ++i)
      EXPECT_EQ(got[i], NthOf(gathered, ranks[i])) << "rank " << ranks[i] << (lanes ? ", lanes" : "");
    EXPECT_TRUE(std::isnan(ValuesAtRanks(values, mask, {n})[0]));  // beyond the count
  }
  SetAvx2Kernels(true);
}

TEST(RankSelect, FiniteValuesOfAMapAndAFlatArray) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> value(0.0f, 3.0f);
  cv::Mat values(64, 300, CV_32F);
  std::vector<float> finite, flat;
  for (int y = 0; y < values.rows; ++y)
    for (int x = 0; x < values.cols; ++x) {
      const bool hole = (x + y) % 5 == 0;
      const float v = value(rng);
      // Holes: NaN, and every 7th an infinity (not finite either).
      values.at<float>(y, x) = !hole   ? v
                               : x % 7 ? std::numeric_limits<float>::quiet_NaN()
                                       : std::numeric_limits<float>::infinity();
      if (!hole) finite.push_back(v);
      flat.push_back(v);
    }
  for (const bool lanes : {false, true}) {
    SetAvx2Kernels(lanes);
    EXPECT_EQ(UpperMedian(values), NthOf(finite, finite.size() / 2));
    EXPECT_EQ(ValuesAtRanks(flat, {flat.size() / 2})[0], NthOf(flat, flat.size() / 2));
    EXPECT_EQ(ValuesAtRanks(flat, {0})[0], *std::min_element(flat.begin(), flat.end()));
    EXPECT_TRUE(std::isnan(UpperMedian(cv::Mat(4, 4, CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN())))));
    // The flat array cut into parts of uneven lengths (one empty, one past a 4096-value segment).
    std::vector<std::vector<float>> parts(4);
    for (std::size_t i = 0; i < flat.size(); ++i) parts[i < 5000 ? 0 : i == 5000 ? 1 : 3].push_back(flat[i]);
    for (const std::size_t rank : {std::size_t{0}, flat.size() / 2, flat.size() / 3, flat.size() - 1})
      EXPECT_EQ(ValuesAtRanks(parts, {rank})[0], NthOf(flat, rank)) << "rank " << rank;
  }
  SetAvx2Kernels(true);
}

TEST(RankSelect, ABinOfManyValuesAsNthElement) {
  // A nearly uniform map (a simulated frame's modulation): most values share one histogram bin
  // (the top 16 bits), which is then resolved by a second histogram of the low bits. Ties, the
  // bin's first and last values, and a few values in the bins around it.
  std::mt19937 rng(17);
  std::uniform_int_distribution<int> low_bits(0, 0xFFFF), coin(0, 9);
  std::uniform_real_distribution<float> elsewhere(40.0f, 70.0f);
  const std::uint32_t bin = 0x425F0000u;  // 55.75 and the floats just above it
  cv::Mat values(300, 311, CV_32F), mask(values.size(), CV_8U);
  std::vector<float> gathered;
  for (int y = 0; y < values.rows; ++y)
    for (int x = 0; x < values.cols; ++x) {
      const std::uint32_t bits = bin | static_cast<std::uint32_t>(x % 13 == 0 ? 0x1234 : low_bits(rng));
      float v;
      std::memcpy(&v, &bits, sizeof v);
      values.at<float>(y, x) = coin(rng) == 0 ? elsewhere(rng) : v;
      mask.at<uchar>(y, x) = coin(rng) < 8 ? 255 : 0;
      if (mask.at<uchar>(y, x)) gathered.push_back(values.at<float>(y, x));
    }
  const std::size_t n = gathered.size();
  std::vector<float> sorted = gathered;
  std::sort(sorted.begin(), sorted.end());
  // The ranks of the bin's smallest and largest values.
  auto in_bin = [&](float v) {
    std::uint32_t b;
    std::memcpy(&b, &v, sizeof b);
    return (b >> 16) == (bin >> 16);
  };
  const std::size_t first_in_bin = std::find_if(sorted.begin(), sorted.end(), in_bin) - sorted.begin();
  const std::size_t last_in_bin = n - 1 - (std::find_if(sorted.rbegin(), sorted.rend(), in_bin) - sorted.rbegin());
  ASSERT_GT(last_in_bin - first_in_bin, 20000u);  // a bin of many values
  const std::vector<std::size_t> ranks{
      n / 2, n - 1 - n / 2, first_in_bin, last_in_bin, first_in_bin - 1, last_in_bin + 1, 0, n - 1};
  for (const bool lanes : {false, true}) {
    SetAvx2Kernels(lanes);
    const std::vector<float> got = ValuesAtRanks(values, mask, ranks);
    for (std::size_t i = 0; i < ranks.size(); ++i)
      EXPECT_EQ(got[i], sorted[ranks[i]]) << "rank " << ranks[i] << (lanes ? ", lanes" : "");
    // The finite values of the map (no mask) and the flat array.
    EXPECT_EQ(ValuesAtRanks(gathered, {n / 3})[0], sorted[n / 3]);
  }
  SetAvx2Kernels(true);
}

}  // namespace
