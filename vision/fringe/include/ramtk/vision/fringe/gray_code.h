#pragma once
// The Gray code of a fringe sequence (manifest.h): projector coordinate u lies in cell
// n = floor(u * 2^bits / extent), clamped to the 2^bits cells; the cell's code word is
// G(n) = n xor (n >> 1), and image j of the block (0 = most significant) shows bit (bits - 1 - j)
// of it, white = 1. The pattern generator and the simulator's renderer draw the code from here;
// the decoders invert it (binary from Gray by a running xor over the images, unwrap.h).

#include <algorithm>
#include <cmath>

namespace ramtk::vision {

// Cell of projector coordinate u among the 2^bits cells across `extent` projector pixels.
inline long long GrayCodeCell(double u, int bits, double extent) {
  const long long cells = 1LL << bits;
  const long long n = static_cast<long long>(std::floor(u * static_cast<double>(cells) / extent));
  return std::max(0LL, std::min(n, cells - 1));
}

// Code word of a cell: n xor (n >> 1).
inline long long GrayCodeWord(long long cell) { return cell ^ (cell >> 1); }

// What image `image` (0 = most significant) of a `bits`-image block shows for `word`: 0 or 1.
inline int GrayCodeImageBit(long long word, int bits, int image) {
  return static_cast<int>((word >> (bits - 1 - image)) & 1);
}

}  // namespace ramtk::vision
