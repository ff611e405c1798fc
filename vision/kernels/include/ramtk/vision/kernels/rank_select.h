#pragma once
// Order statistics of large sets of non-negative floats (medians of a frame's modulation, of the
// match and point sigmas): what std::nth_element gives on the gathered values, without gathering
// them. The bit patterns of non-negative floats sort as the values, so a parallel histogram of
// their top 16 bits finds the bin holding each rank; only those bins' values are gathered and
// selected from.
#include <cstddef>
#include <opencv2/core.hpp>
#include <vector>

namespace ramtk::vision::detail {

// The values at `ranks` (0-based, ascending order) among the pixels of `values` (CV_32F) where
// `mask` (CV_8U, same size) is set, or, with an empty mask, among its finite pixels. Every
// selected value must be >= 0. NaN for a rank beyond the count.
std::vector<float> ValuesAtRanks(const cv::Mat& values, const cv::Mat& mask, const std::vector<std::size_t>& ranks);

// The value at rank count / 2 among the finite pixels of `values` (CV_32F, each >= 0): the
// element std::nth_element puts in the middle of the gathered finite values. NaN if none.
float UpperMedian(const cv::Mat& values);

// The same over a flat array (every value finite and >= 0).
std::vector<float> ValuesAtRanks(const std::vector<float>& values, const std::vector<std::size_t>& ranks);

// The same over the values of several arrays together (every value finite and >= 0), without
// joining them into one.
std::vector<float> ValuesAtRanks(const std::vector<std::vector<float>>& parts, const std::vector<std::size_t>& ranks);

}  // namespace ramtk::vision::detail
