#pragma once
// The pixels of a source row the stereo match searches (stereo_walk.cpp, RunPass): valid (mask
// set, finite coordinate), not noisy (coordinate sigma within the pass's limit) and, with the
// left-right check's reach map, reachable by some back match. Listed once per row before the
// walk, eight pixels at a time on CPUs with AVX2; the walk then goes from entry to entry.
#include <opencv2/core.hpp>

namespace ramtk::vision::detail {

// Per row: the valid pixels, and of them the noisy ones and the unreachable ones (not searched).
struct SearchCounts {
  long valid = 0, noisy = 0, unreachable = 0;
};

// Lists the columns of `width` pixels to search into xs (ascending; xs holds width + 8 entries,
// the last eight scratch) and returns their count. `reach` may be null (every pixel reachable).
// A pixel is noisy unless sigma <= max_sigma, compared in double as the walk did (NaN is noisy).
int ListSearchedPixels(const uchar* mask, const float* coord, const float* sigma, const uchar* reach, int width,
                       double max_sigma, int* xs, SearchCounts* counts);

// Pass::cell_ok of one row of n cells between coordinate rows r0 and r1 (each n + 1 long): 1
// where the cell's four corners are finite and span at most max_span (the span in double, from
// the float extremes), else 0. Eight cells at a time on CPUs with AVX2.
void CellRow(const float* r0, const float* r1, int n, double max_span, uchar* ok);

// NaN into n values (the walk's output and inverse-depth rows before it reaches them), 32 bytes
// at a time on CPUs with AVX2.
void FillNaN(float* row, int n);
void FillNaN(double* row, int n);

}  // namespace ramtk::vision::detail
