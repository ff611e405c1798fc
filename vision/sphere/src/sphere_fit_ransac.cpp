// Sphere candidates by RANSAC: closed-form spheres through 4 points drawn from one spatial
// neighbourhood (so a small ball in a large cloud is still sampled often), a radius gate from
// the prior, scoring on a strided subset of the neighbourhood, and a local optimisation (LO)
// of every new best candidate by iterated algebraic fits on its inliers.

#include <immintrin.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/vision/kernels/fast_round.h"
#include "ramtk/vision/sphere/detail/sphere_fit_internal.h"

namespace ramtk::vision {

bool SphereThroughFourPoints(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                             const Eigen::Vector3d& d, Eigen::Vector3d* centre, double* radius) {
  // With q_k = p_k - a the centre offset x satisfies 2 q_k . x = |q_k|^2 (k = 1..3).
  Eigen::Matrix3d m;
  m.row(0) = 2 * (b - a);
  m.row(1) = 2 * (c - a);
  m.row(2) = 2 * (d - a);
  const Eigen::Vector3d rhs((b - a).squaredNorm(), (c - a).squaredNorm(), (d - a).squaredNorm());
  // Coplanar points: det ~ 0 relative to the scale of the rows.
  const double scale = m.row(0).norm() * m.row(1).norm() * m.row(2).norm();
  const double det = m.determinant();
  if (!(scale > 0) || std::abs(det) < 1e-9 * scale) return false;
  const Eigen::Vector3d x = m.partialPivLu().solve(rhs);
  if (!x.allFinite()) return false;
  *centre = a + x;
  *radius = x.norm();
  return true;
}

namespace sphere_internal {

int64_t PointGrid::Pack(int64_t i, int64_t j, int64_t k) {
  // 21 bits per axis, offset to be non-negative; cells beyond +-1e6 wrap (harmless: a hash).
  constexpr int64_t kOff = 1 << 20, kMask = (1 << 21) - 1;
  return (((i + kOff) & kMask) << 42) | (((j + kOff) & kMask) << 21) | ((k + kOff) & kMask);
}

namespace {

// The cell index floor(g), by fast_round.h's exact floor (no rounding instruction before SSE4.1).
inline int64_t FloorToInt64(double g) { return static_cast<int64_t>(detail::Floor(g)); }

}  // namespace

int64_t PointGrid::Key(const Eigen::Vector3d& x) const {
  const Eigen::Vector3d g = (x - origin_) / cell_;
  return Pack(FloorToInt64(g.x()), FloorToInt64(g.y()), FloorToInt64(g.z()));
}

namespace {

// PointGrid::Key of the points active[k .. k + 4) on AVX2 lanes: (x - origin) / cell and its floor
// per axis exactly as Key takes them, packed as Pack packs them. False (keys not written) if a
// cell index is beyond +-2^30 (Key and Pack then, one by one).
RAMTK_AVX2 bool KeysOfFour(const Eigen::Vector3f* points, const int* idx, const Eigen::Vector3d& origin, double cell,
                           int64_t* keys) {
  const float *p0 = points[idx[0]].data(), *p1 = points[idx[1]].data(), *p2 = points[idx[2]].data(),
              *p3 = points[idx[3]].data();
  const __m256d c = _mm256_set1_pd(cell);
  __m256i packed = _mm256_setzero_si256();
  const __m256d limit = _mm256_set1_pd(1073741824.0);  // 2^30
  int inside = 0xF;
  for (int axis = 0; axis < 3; ++axis) {
    const __m256d x = _mm256_cvtps_pd(_mm_setr_ps(p0[axis], p1[axis], p2[axis], p3[axis]));
    const __m256d g = _mm256_floor_pd(_mm256_div_pd(_mm256_sub_pd(x, _mm256_set1_pd(origin[axis])), c));
    inside &= _mm256_movemask_pd(_mm256_and_pd(
        _mm256_cmp_pd(g, limit, _CMP_LT_OQ), _mm256_cmp_pd(g, _mm256_sub_pd(_mm256_setzero_pd(), limit), _CMP_GT_OQ)));
    // ((i + 2^20) & (2^21 - 1)) at bit 42, 21 or 0.
    const __m256i i = _mm256_cvtepi32_epi64(_mm256_cvttpd_epi32(g));
    const __m256i field =
        _mm256_and_si256(_mm256_add_epi64(i, _mm256_set1_epi64x(1 << 20)), _mm256_set1_epi64x((1 << 21) - 1));
    packed = _mm256_or_si256(packed, _mm256_sll_epi64(field, _mm_cvtsi32_si128(42 - 21 * axis)));
  }
  if (inside != 0xF) return false;
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(keys), packed);
  return true;
}

}  // namespace

PointGrid::PointGrid(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& active, double cell_mm)
    : cell_(cell_mm),
      origin_(active.empty() ? Eigen::Vector3d(Eigen::Vector3d::Zero())
                             : Eigen::Vector3d(points[active.front()].cast<double>())) {
  // One array of the active indices grouped by cell, every cell's in the order of `active`, as
  // one pass appending to per-cell lists would give (that pass took 82 ms for a thesis frame's
  // 6.4 M points, its parallel version with per-chunk lists merged in order 55-70 ms). Points come
  // in image order, so consecutive points mostly share a cell: chunks of the active list are cut
  // into runs of one cell in parallel; the runs are given their places in chunk order (few: a
  // run is tens of points); then each chunk copies its runs' indices into place in parallel.
  constexpr std::size_t kChunk = 1 << 16;
  const std::size_t chunks = (active.size() + kChunk - 1) / kChunk;
  struct Run {
    int64_t key = 0;
    std::size_t first = 0, size = 0;  // active[first, first + size)
    Span* cell = nullptr;             // its cell (unordered_map elements stay put on rehash)
    std::size_t to = 0;               // its place in index_
  };
  std::vector<std::vector<Run>> runs(chunks);
  const bool lanes = detail::Avx2Kernels();
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    std::vector<Run>& out = runs[c];
    const std::size_t end = std::min(active.size(), (c + 1) * kChunk);
    auto add = [&](std::size_t k, int64_t key) {
      if (out.empty() || out.back().key != key) out.push_back({key, k, 0, nullptr, 0});
      ++out.back().size;
    };
    std::size_t k = c * kChunk;
    if (lanes) {
      int64_t keys[4];
      for (; k + 4 <= end; k += 4) {
        if (!KeysOfFour(points.data(), active.data() + k, origin_, cell_, keys))
          for (int i = 0; i < 4; ++i) keys[i] = Key(points[active[k + i]].cast<double>());
        for (int i = 0; i < 4; ++i) add(k + i, keys[i]);
      }
    }
    for (; k < end; ++k) add(k, Key(points[active[k]].cast<double>()));
  });
  // Cell sizes, then each cell's place (in the order cells first appear), then each run's.
  std::vector<int64_t> order;
  for (std::vector<Run>& chunk : runs)
    for (Run& r : chunk) {
      auto [it, fresh] = cells_.try_emplace(r.key);
      if (fresh) order.push_back(r.key);
      r.cell = &it->second;
      r.cell->size += r.size;
    }
  std::size_t next = 0;
  for (const int64_t key : order) {
    Span& span = cells_[key];
    span.begin = next;
    next += span.size;
    span.size = 0;  // counts again below, as the runs are placed
  }
  for (std::vector<Run>& chunk : runs)
    for (Run& r : chunk) {
      r.to = r.cell->begin + r.cell->size;
      r.cell->size += r.size;
    }
  index_.resize(active.size());
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    for (const Run& r : runs[c])
      std::copy(active.begin() + static_cast<std::ptrdiff_t>(r.first),
                active.begin() + static_cast<std::ptrdiff_t>(r.first + r.size),
                index_.begin() + static_cast<std::ptrdiff_t>(r.to));
  });
}

const CellNeighbourhood& PointGrid::Neighbourhood(const Eigen::Vector3d& x) {
  const Eigen::Vector3d g = (x - origin_) / cell_;
  const int64_t ci = FloorToInt64(g.x()), cj = FloorToInt64(g.y()), ck = FloorToInt64(g.z());
  const int64_t key = Pack(ci, cj, ck);
  auto cached = cache_.find(key);
  if (cached != cache_.end()) return cached->second;
  CellNeighbourhood& out = cache_[key];
  for (int64_t di = -1; di <= 1; ++di)
    for (int64_t dj = -1; dj <= 1; ++dj)
      for (int64_t dk = -1; dk <= 1; ++dk) {
        auto it = cells_.find(Pack(ci + di, cj + dj, ck + dk));
        if (it == cells_.end() || it->second.size == 0) continue;
        out.cells_[out.count_] = index_.data() + it->second.begin;
        out.start_[out.count_] = out.size_;
        out.size_ += it->second.size;
        ++out.count_;
      }
  out.start_[out.count_] = out.size_;
  return out;
}

bool FitAlgebraic(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& indices, Eigen::Vector3d* centre,
                  double* radius) {
  if (indices.size() < 4) return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i : indices) mean += points[i].cast<double>();
  mean /= static_cast<double>(indices.size());
  // |q|^2 = 2 q.x + d with q = p - mean, x the centre offset and d = R^2 - |x|^2.
  Eigen::Matrix4d ata = Eigen::Matrix4d::Zero();
  Eigen::Vector4d atb = Eigen::Vector4d::Zero();
  for (int i : indices) {
    const Eigen::Vector3d q = points[i].cast<double>() - mean;
    const Eigen::Vector4d row(2 * q.x(), 2 * q.y(), 2 * q.z(), 1.0);
    ata.noalias() += row * row.transpose();
    atb += row * q.squaredNorm();
  }
  Eigen::LDLT<Eigen::Matrix4d> ldlt(ata);
  if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-14)) return false;
  const Eigen::Vector4d sol = ldlt.solve(atb);
  const double r2 = sol(3) + sol.head<3>().squaredNorm();
  if (!sol.allFinite() || !(r2 > 0)) return false;
  *centre = mean + sol.head<3>();
  *radius = std::sqrt(r2);
  return true;
}

namespace {

// The indices idx[0, n) within the band, counted, and with `out` appended in order (scalar).
int WithinBandScalar(const std::vector<Eigen::Vector3f>& points, const int* idx, int n, const Eigen::Vector3d& centre,
                     double radius, double band, std::vector<int>* out) {
  int count = 0;
  for (int k = 0; k < n; ++k) {
    if (!(std::abs((points[idx[k]].cast<double>() - centre).norm() - radius) <= band)) continue;
    ++count;
    if (out) out->push_back(idx[k]);
  }
  return count;
}

// |‖p - c‖ - R| of the points idx[0, 4) on AVX2 lanes, as Eigen computes it: the float point
// widened, the difference, the squares summed as x^2 + (y^2 + z^2) (Eigen's reduction of a
// 3-vector), the square root; std::abs clears the sign bit.
RAMTK_AVX2_INLINE __m256d OffShell4(const Eigen::Vector3f* pts, const int* idx, __m256d cx, __m256d cy, __m256d cz,
                                    __m256d r) {
  const float *p0 = pts[idx[0]].data(), *p1 = pts[idx[1]].data(), *p2 = pts[idx[2]].data(), *p3 = pts[idx[3]].data();
  const __m256d dx = _mm256_sub_pd(_mm256_cvtps_pd(_mm_setr_ps(p0[0], p1[0], p2[0], p3[0])), cx);
  const __m256d dy = _mm256_sub_pd(_mm256_cvtps_pd(_mm_setr_ps(p0[1], p1[1], p2[1], p3[1])), cy);
  const __m256d dz = _mm256_sub_pd(_mm256_cvtps_pd(_mm_setr_ps(p0[2], p1[2], p2[2], p3[2])), cz);
  const __m256d d2 = _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_add_pd(_mm256_mul_pd(dy, dy), _mm256_mul_pd(dz, dz)));
  const __m256d sign = _mm256_castsi256_pd(_mm256_set1_epi64x(static_cast<long long>(0x8000000000000000ull)));
  return _mm256_andnot_pd(sign, _mm256_sub_pd(_mm256_sqrt_pd(d2), r));
}

// The same, four points at a time on AVX2 lanes (OffShell4).
RAMTK_AVX2 int WithinBandAvx2(const std::vector<Eigen::Vector3f>& points, const int* idx, int n,
                              const Eigen::Vector3d& centre, double radius, double band, std::vector<int>* out) {
  const __m256d cx = _mm256_set1_pd(centre.x()), cy = _mm256_set1_pd(centre.y()), cz = _mm256_set1_pd(centre.z());
  const __m256d r = _mm256_set1_pd(radius), b = _mm256_set1_pd(band);
  const Eigen::Vector3f* pts = points.data();
  int count = 0, k = 0;
  for (; k + 4 <= n; k += 4) {
    const __m256d off = OffShell4(pts, idx + k, cx, cy, cz, r);
    int in = _mm256_movemask_pd(_mm256_cmp_pd(off, b, _CMP_LE_OQ));
    count += __builtin_popcount(static_cast<unsigned>(in));
    if (out)
      for (; in; in &= in - 1) out->push_back(idx[k + __builtin_ctz(static_cast<unsigned>(in))]);
  }
  return count + WithinBandScalar(points, idx + k, n - k, centre, radius, band, out);
}

// SplitByDistance one by one, and four points at a time on AVX2 lanes.
void SplitScalar(const std::vector<Eigen::Vector3f>& points, const int* idx, int n, const Eigen::Vector3d& centre,
                 double radius, double outer, double inner, std::vector<int>* near, std::vector<int>* in_band) {
  for (int k = 0; k < n; ++k) {
    const int i = idx[k];
    const double r = std::abs((points[i].cast<double>() - centre).norm() - radius);
    if (r <= outer) near->push_back(i);
    if (r <= inner) in_band->push_back(i);
  }
}

RAMTK_AVX2 void SplitAvx2(const std::vector<Eigen::Vector3f>& points, const int* idx, int n,
                          const Eigen::Vector3d& centre, double radius, double outer, double inner,
                          std::vector<int>* near, std::vector<int>* in_band) {
  const __m256d cx = _mm256_set1_pd(centre.x()), cy = _mm256_set1_pd(centre.y()), cz = _mm256_set1_pd(centre.z());
  const __m256d r = _mm256_set1_pd(radius), o = _mm256_set1_pd(outer), in = _mm256_set1_pd(inner);
  const Eigen::Vector3f* pts = points.data();
  int k = 0;
  for (; k + 4 <= n; k += 4) {
    const __m256d off = OffShell4(pts, idx + k, cx, cy, cz, r);
    int a = _mm256_movemask_pd(_mm256_cmp_pd(off, o, _CMP_LE_OQ));
    int b = _mm256_movemask_pd(_mm256_cmp_pd(off, in, _CMP_LE_OQ));
    for (; a; a &= a - 1) near->push_back(idx[k + __builtin_ctz(static_cast<unsigned>(a))]);
    for (; b; b &= b - 1) in_band->push_back(idx[k + __builtin_ctz(static_cast<unsigned>(b))]);
  }
  SplitScalar(points, idx + k, n - k, centre, radius, outer, inner, near, in_band);
}

}  // namespace

void SplitByDistance(const std::vector<Eigen::Vector3f>& points, const int* indices, int n,
                     const Eigen::Vector3d& centre, double radius, double outer, double inner, std::vector<int>* near,
                     std::vector<int>* in_band) {
  if (detail::Avx2Kernels())
    SplitAvx2(points, indices, n, centre, radius, outer, inner, near, in_band);
  else
    SplitScalar(points, indices, n, centre, radius, outer, inner, near, in_band);
}

int WithinBand(const std::vector<Eigen::Vector3f>& points, const CellNeighbourhood& pool, std::size_t first,
               std::size_t stride, const Eigen::Vector3d& centre, double radius, double band, std::vector<int>* out) {
  if (out) out->clear();
  const bool lanes = detail::Avx2Kernels();
  constexpr int kBatch = 256;
  int idx[kBatch];
  int n = 0, count = 0;
  auto within = [&](const int* indices, int count_of) {
    return lanes ? WithinBandAvx2(points, indices, count_of, centre, radius, band, out)
                 : WithinBandScalar(points, indices, count_of, centre, radius, band, out);
  };
  if (stride == 1 && first == 0) {  // each cell's indices as they lie
    pool.ForEachRun([&](const int* indices, std::size_t size) { count += within(indices, static_cast<int>(size)); });
    return count;
  }
  auto flush = [&] {
    count += within(idx, n);
    n = 0;
  };
  pool.ForEachStrided(first, stride, [&](int i) {
    idx[n++] = i;
    if (n == kBatch) flush();
  });
  flush();
  return count;
}

Candidate FindCandidate(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& active, double band_mm,
                        double radius_lo, double radius_hi, const SphereFitOptions& options, std::mt19937_64& rng) {
  Candidate best;
  if (active.size() < 4) {
    best.reason = "only " + std::to_string(active.size()) + " points left";
    return best;
  }
  // A sphere point's sphere lies within 2 R of it; cells of edge R_hi keep most of it in the
  // 27-cell neighbourhood and, around a centre, all of it.
  PointGrid grid(points, active, radius_hi);
  const double min_separation = 0.25 * radius_lo;  // well-spread samples give usable spheres
  const double min_sep2 = min_separation * min_separation;
  std::uniform_int_distribution<size_t> pick_active(0, active.size() - 1);
  std::vector<int> inliers, trial;
  double needed = options.max_iterations;
  int it = 0;
  for (; it < options.max_iterations && (it < options.min_iterations || it < needed); ++it) {
    const int i0 = active[pick_active(rng)];
    const CellNeighbourhood& nb = grid.Neighbourhood(points[i0].cast<double>());
    if (nb.size() < 4) continue;
    std::uniform_int_distribution<size_t> pick_nb(0, nb.size() - 1);
    Eigen::Vector3d s[4] = {points[i0].cast<double>(), {}, {}, {}};
    bool spread = true;
    for (int k = 1; k < 4 && spread; ++k) {
      s[k] = points[nb[pick_nb(rng)]].cast<double>();
      for (int j = 0; j < k; ++j) spread = spread && (s[k] - s[j]).squaredNorm() >= min_sep2;
    }
    if (!spread) continue;
    Eigen::Vector3d centre;
    double radius = 0;
    if (!SphereThroughFourPoints(s[0], s[1], s[2], s[3], &centre, &radius)) continue;
    if (radius < radius_lo || radius > radius_hi) continue;
    ++best.radius_ok_samples;
    // Score on a strided subset of the points around the candidate centre.
    const CellNeighbourhood& around = grid.Neighbourhood(centre);
    const size_t stride = std::max<size_t>(1, around.size() / static_cast<size_t>(options.max_scoring_points));
    const int count = WithinBand(points, around, rng() % stride, stride, centre, radius, band_mm, nullptr);
    const double estimate = static_cast<double>(count) * static_cast<double>(stride);
    if (estimate <= best.inliers) continue;
    // Local optimisation: algebraic refits on the full inlier set while it grows.
    WithinBand(points, around, 0, 1, centre, radius, band_mm, &inliers);
    for (int lo = 0; lo < 5; ++lo) {
      Eigen::Vector3d c2;
      double r2 = 0;
      if (!FitAlgebraic(points, inliers, &c2, &r2) || r2 < radius_lo || r2 > radius_hi) break;
      WithinBand(points, grid.Neighbourhood(c2), 0, 1, c2, r2, band_mm, &trial);
      if (trial.size() <= inliers.size()) break;
      centre = c2;
      radius = r2;
      inliers.swap(trial);
    }
    if (static_cast<int>(inliers.size()) <= best.inliers) continue;
    best.found = true;
    best.centre = centre;
    best.radius = radius;
    best.inliers = static_cast<int>(inliers.size());
    // Samples needed: P(first point on the sphere) x P(the other three on it | its neighbourhood).
    const double share_all = static_cast<double>(best.inliers) / static_cast<double>(active.size());
    const double share_nb =
        static_cast<double>(best.inliers) / static_cast<double>(std::max<size_t>(1, grid.Neighbourhood(centre).size()));
    const double w = std::clamp(share_all * std::pow(std::min(1.0, share_nb), 3), 1e-12, 1.0 - 1e-12);
    needed = std::log(1.0 - options.confidence) / std::log1p(-w);
  }
  best.iterations = it;
  if (!best.found) {
    best.reason = best.radius_ok_samples == 0
                      ? "no candidate sphere with radius in [" + std::to_string(radius_lo) + ", " +
                            std::to_string(radius_hi) + "] mm among " + std::to_string(it) + " samples"
                      : "no candidate sphere";
  }
  return best;
}

}  // namespace sphere_internal
}  // namespace ramtk::vision
