// Order statistics by a parallel histogram of float bit patterns (rank_select.h).
#include "ramtk/vision/kernels/rank_select.h"

#include <immintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>

#include "ramtk/vision/kernels/avx2.h"

namespace ramtk::vision::detail {
namespace {

constexpr int kBins = 1 << 15;  // bits >> 16 of a non-negative float (sign bit clear)

int BinOf(float v) {
  std::uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  return static_cast<int>(std::min<std::uint32_t>(bits >> 16, kBins - 1));
}

// A run of values and its mask (nullptr: every finite value counts).
struct Segment {
  const float* values = nullptr;
  const uchar* mask = nullptr;
  int length = 0;
};

bool Counts(const Segment& s, int x) { return s.mask ? s.mask[x] != 0 : std::isfinite(s.values[x]); }

// Whether the eight mask bytes at m are all zero.
bool MaskedEight(const uchar* m) {
  std::uint64_t v;
  std::memcpy(&v, m, sizeof v);
  return v == 0;
}

// The segment's values that count, into the even / odd halves of a histogram (the scalar loop).
void CountSegment(const Segment& s, std::uint32_t* even, std::uint32_t* odd) {
  int x = 0;
  for (; x + 1 < s.length; x += 2) {
    if (s.mask && x + 8 <= s.length && MaskedEight(s.mask + x)) {
      x += 6;  // eight masked values at once (the loop adds 2)
      continue;
    }
    if (Counts(s, x)) ++even[BinOf(s.values[x])];
    if (Counts(s, x + 1)) ++odd[BinOf(s.values[x + 1])];
  }
  if (x < s.length && Counts(s, x)) ++even[BinOf(s.values[x])];
}

// What the gather pass collects: per wanted rank i, the values of bin bins[i] into lists[i] or,
// for a full bin (low[i] set), the counts of their low 16 bits into low[i] (a value in several
// equal bins: the first rank's).
struct Targets {
  const std::vector<int>& bins;
  std::vector<std::vector<float>>& lists;
  std::vector<std::vector<std::uint32_t>>& low;  // empty where the rank's bin is gathered
  void Add(std::size_t i, float v) const {
    if (!low[i].empty()) {
      std::uint32_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      ++low[i][bits & 0xFFFFu];
    } else {
      lists[i].push_back(v);
    }
  }
};

// The values of bin bins[i] into lists[i] (a value in several equal bins: the first's list).
void GatherSegment(const Segment& s, const Targets& t) {
  const std::vector<int>& bins = t.bins;
  for (int x = 0; x < s.length; ++x) {
    if (s.mask && x + 8 <= s.length && MaskedEight(s.mask + x)) {
      x += 7;  // eight masked values at once
      continue;
    }
    if (!Counts(s, x)) continue;
    const int bin = BinOf(s.values[x]);
    for (std::size_t i = 0; i < bins.size(); ++i)
      if (bin == bins[i]) {
        t.Add(i, s.values[x]);
        break;  // equal bins: the first rank's list serves both (Select)
      }
  }
}

// Of eight values at x, those that count (bit i: value x + i), and their bins.
RAMTK_AVX2_INLINE int EightThatCount(const Segment& s, int x, __m256i* bins) {
  const __m256i bits = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s.values + x));
  int count;
  if (s.mask) {
    const __m128i m = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(s.mask + x));
    count = ~_mm_movemask_epi8(_mm_cmpeq_epi8(m, _mm_setzero_si128())) & 0xFF;
  } else {  // finite: the exponent not all ones
    const __m256i exponent = _mm256_set1_epi32(0x7f800000);
    const __m256i inf_or_nan = _mm256_cmpeq_epi32(_mm256_and_si256(bits, exponent), exponent);
    count = ~_mm256_movemask_ps(_mm256_castsi256_ps(inf_or_nan)) & 0xFF;
  }
  // BinOf: bits >> 16, at most kBins - 1.
  *bins = _mm256_min_epu32(_mm256_srli_epi32(bits, 16), _mm256_set1_epi32(kBins - 1));
  return count;
}

// CountSegment, eight values at a time on AVX2 lanes (the same counts).
RAMTK_AVX2 void CountSegmentAvx2(const Segment& s, std::uint32_t* even, std::uint32_t* odd) {
  int x = 0;
  alignas(32) std::uint32_t b[8];
  for (; x + 8 <= s.length; x += 8) {
    if (s.mask && MaskedEight(s.mask + x)) continue;
    __m256i bins;
    int count = EightThatCount(s, x, &bins);
    if (!count) continue;
    // Eight values in one bin (most of a smooth map): one addition, not eight increments of one
    // counter, each waiting for the last.
    const __m256i first = _mm256_permutevar8x32_epi32(bins, _mm256_setzero_si256());
    if (_mm256_movemask_epi8(_mm256_cmpeq_epi32(bins, first)) == -1) {
      even[_mm256_cvtsi256_si32(bins)] += static_cast<std::uint32_t>(__builtin_popcount(static_cast<unsigned>(count)));
      continue;
    }
    _mm256_store_si256(reinterpret_cast<__m256i*>(b), bins);
    for (; count; count &= count - 1) {
      const int i = __builtin_ctz(static_cast<unsigned>(count));
      ++((i & 1) ? odd : even)[b[i]];
    }
  }
  for (; x < s.length; ++x)
    if (Counts(s, x)) ++((x & 1) ? odd : even)[BinOf(s.values[x])];
}

// GatherSegment, eight values at a time on AVX2 lanes (the same lists, in the same order).
RAMTK_AVX2 void GatherSegmentAvx2(const Segment& s, const Targets& t) {
  const std::vector<int>& bins = t.bins;
  int x = 0;
  for (; x + 8 <= s.length; x += 8) {
    if (s.mask && MaskedEight(s.mask + x)) continue;
    __m256i vb;
    const int count = EightThatCount(s, x, &vb);
    if (!count) continue;
    int in_bin[8] = {-1, -1, -1, -1, -1, -1, -1, -1};  // per value: the first rank whose bin it is in
    int any = 0;
    for (std::size_t i = bins.size(); i-- > 0;) {
      const int m = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(vb, _mm256_set1_epi32(bins[i])))) & count;
      for (int mm = m; mm; mm &= mm - 1) in_bin[__builtin_ctz(static_cast<unsigned>(mm))] = static_cast<int>(i);
      any |= m;
    }
    for (; any; any &= any - 1) {
      const int k = __builtin_ctz(static_cast<unsigned>(any));
      t.Add(static_cast<std::size_t>(in_bin[k]), s.values[x + k]);
    }
  }
  Segment tail = s;
  tail.values += x;
  if (tail.mask) tail.mask += x;
  tail.length -= x;
  GatherSegment(tail, t);
}

// `ranks_of(count)`: the ranks wanted, given how many values count.
std::vector<float> Select(const std::vector<Segment>& segments,
                          const std::function<std::vector<std::size_t>(std::size_t)>& ranks_of) {
  // Histograms per thread, added at the end (integer counts: the order does not matter). The
  // functional parallel_reduce, used before, copied a 256 KB histogram into every task and join.
  // Each thread counts even and odd positions into two halves: neighbouring values of a smooth
  // map mostly fall in one bin, and one counter would make each increment wait for the last.
  // 32-bit counters (a segment list holds < 2^32 values per half) keep the pair at 256 KB.
  tbb::enumerable_thread_specific<std::vector<std::uint32_t>> per_thread(
      [] { return std::vector<std::uint32_t>(2 * kBins, 0); });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, segments.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::vector<std::uint32_t>& h = per_thread.local();
                      std::uint32_t* even = h.data();
                      std::uint32_t* odd = h.data() + kBins;
                      const bool lanes = Avx2Kernels();
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        if (lanes)
                          CountSegmentAvx2(segments[i], even, odd);
                        else
                          CountSegment(segments[i], even, odd);
                      }
                    });
  std::vector<std::uint64_t> hist(kBins, 0);
  for (const std::vector<std::uint32_t>& h : per_thread)
    for (int i = 0; i < kBins; ++i) hist[i] += static_cast<std::uint64_t>(h[i]) + h[kBins + i];
  std::size_t count = 0;
  for (const std::uint64_t h : hist) count += h;
  const std::vector<std::size_t> ranks = ranks_of(count);
  // The bin holding each rank, then one pass gathering those bins' values.
  std::vector<int> bins;
  std::vector<std::size_t> below;
  for (const std::size_t rank : ranks) {
    std::size_t b = 0;
    int bin = 0;
    while (bin < kBins - 1 && b + hist[bin] <= rank) b += hist[bin++];
    bins.push_back(bin);
    below.push_back(b);
  }
  // A bin of many values (a nearly uniform map puts 6 % of a thesis frame's modulations in one)
  // is resolved by a second histogram over the values' low 16 bits instead of gathering the
  // values for nth_element (their order is that of the bits); the other bins' values are
  // gathered. Bins of infinities and NaNs are always gathered.
  constexpr std::uint64_t kGatherAtMost = 1 << 14;
  constexpr int kLow = 1 << 16;
  std::vector<char> full(ranks.size(), 0);
  for (std::size_t i = 0; i < ranks.size(); ++i) {
    std::size_t first = 0;
    while (bins[first] != bins[i]) ++first;
    full[i] = first == i && hist[bins[i]] > kGatherAtMost && bins[i] < 0x7F80;  // below infinity's bits
  }
  // Per thread, then joined: nth_element's value does not depend on the order of the list, nor a
  // histogram on the order of its counts.
  struct Gathered {
    std::vector<std::vector<float>> lists;
    std::vector<std::vector<std::uint32_t>> low;
  };
  tbb::enumerable_thread_specific<Gathered> gathered([&] {
    Gathered g;
    g.lists.resize(ranks.size());
    g.low.resize(ranks.size());
    for (std::size_t i = 0; i < ranks.size(); ++i)
      if (full[i]) g.low[i].assign(kLow, 0);
    return g;
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, segments.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      Gathered& g = gathered.local();
                      const Targets t{bins, g.lists, g.low};
                      const bool lanes = Avx2Kernels();
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        if (lanes)
                          GatherSegmentAvx2(segments[k], t);
                        else
                          GatherSegment(segments[k], t);
                      }
                    });
  std::vector<std::vector<float>> in_bin(ranks.size());
  std::vector<std::vector<std::uint64_t>> low(ranks.size());
  for (std::size_t i = 0; i < ranks.size(); ++i)
    if (full[i]) low[i].assign(kLow, 0);
  for (const Gathered& g : gathered)
    for (std::size_t i = 0; i < ranks.size(); ++i) {
      in_bin[i].insert(in_bin[i].end(), g.lists[i].begin(), g.lists[i].end());
      if (full[i])
        for (int b = 0; b < kLow; ++b) low[i][b] += g.low[i][b];
    }
  std::vector<float> out;
  for (std::size_t i = 0; i < ranks.size(); ++i) {
    std::size_t first = 0;  // the first rank in the same bin holds the bin's values
    while (bins[first] != bins[i]) ++first;
    const std::size_t in_this_bin = hist[bins[i]];
    if (ranks[i] < below[i] || ranks[i] - below[i] >= in_this_bin) {
      out.push_back(std::numeric_limits<float>::quiet_NaN());
      continue;
    }
    const std::size_t k = ranks[i] - below[i];
    if (full[first]) {
      // The k-th value by its low bits: the first low bits whose running count passes k.
      std::uint64_t seen = 0;
      int b = 0;
      while (seen + low[first][b] <= k) seen += low[first][b++];
      const std::uint32_t bits = static_cast<std::uint32_t>(bins[i]) << 16 | static_cast<std::uint32_t>(b);
      float v;
      std::memcpy(&v, &bits, sizeof v);
      out.push_back(v);
      continue;
    }
    std::vector<float>& vals = in_bin[first];
    std::nth_element(vals.begin(), vals.begin() + static_cast<std::ptrdiff_t>(k), vals.end());
    out.push_back(vals[k]);
  }
  return out;
}

// One segment per row of `values` (CV_32F) with its mask row (empty mask: finite values count).
std::vector<Segment> RowSegments(const cv::Mat& values, const cv::Mat& mask) {
  CV_Assert(values.type() == CV_32F && (mask.empty() || (mask.type() == CV_8U && mask.size() == values.size())));
  std::vector<Segment> segments(static_cast<std::size_t>(values.rows));
  for (int y = 0; y < values.rows; ++y)
    segments[y] = {values.ptr<float>(y), mask.empty() ? nullptr : mask.ptr<uchar>(y), values.cols};
  return segments;
}

}  // namespace

std::vector<float> ValuesAtRanks(const cv::Mat& values, const cv::Mat& mask, const std::vector<std::size_t>& ranks) {
  return Select(RowSegments(values, mask), [&](std::size_t) { return ranks; });
}

float UpperMedian(const cv::Mat& values) {
  return Select(RowSegments(values, cv::Mat()),
                [](std::size_t count) { return std::vector<std::size_t>{count / 2}; })[0];
}

namespace {

// Segments of at most 4096 values over an array (every value counts).
void AppendSegments(const std::vector<float>& values, std::vector<Segment>* segments) {
  constexpr std::size_t kSegment = 4096;
  for (std::size_t i = 0; i < values.size(); i += kSegment)
    segments->push_back({values.data() + i, nullptr, static_cast<int>(std::min(kSegment, values.size() - i))});
}

}  // namespace

std::vector<float> ValuesAtRanks(const std::vector<float>& values, const std::vector<std::size_t>& ranks) {
  std::vector<Segment> segments;
  AppendSegments(values, &segments);
  return Select(segments, [&](std::size_t) { return ranks; });
}

std::vector<float> ValuesAtRanks(const std::vector<std::vector<float>>& parts, const std::vector<std::size_t>& ranks) {
  std::vector<Segment> segments;
  for (const std::vector<float>& values : parts) AppendSegments(values, &segments);
  return Select(segments, [&](std::size_t) { return ranks; });
}

}  // namespace ramtk::vision::detail
