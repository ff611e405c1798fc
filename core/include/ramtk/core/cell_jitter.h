#pragma once
// A fixed sub-pixel offset per pixel cell, for renderers that jitter their rays reproducibly (the
// same cell gives the same offset in every render and in any self-check that recomputes it).

#include <cstdint>

namespace ramtk {

// Offset in [0, 1) along `axis` (0: x, 1: y) of cell (x, y): a 64-bit mix of the cell's indices.
inline double CellJitter(int x, int y, int axis) {
  std::uint64_t h = (static_cast<std::uint64_t>(x) << 32) ^ static_cast<std::uint64_t>(y) ^ (axis ? 0x5bd1e995ULL : 0);
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ULL;
  h ^= h >> 33;
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

}  // namespace ramtk
