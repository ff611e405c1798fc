// The rectified grid of the stereo match's rectified search (stereo_rectified_grid.h).
#include "ramtk/vision/stereo/detail/stereo_rectified_grid.h"

#include <immintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "ramtk/vision/kernels/avx2.h"
#include "ramtk/vision/kernels/distort_lanes.h"
#include "ramtk/vision/kernels/fast_round.h"

namespace ramtk::vision::detail {

RectifiedPair MakeRectifiedPair(const StereoCalibration& calibration) {
  const Mat3 R = calibration.right_from_left.linear();
  const Vec3 T = calibration.right_from_left.translation();
  RectifiedPair pair;
  const Vec3 right_centre_in_left = -R.transpose() * T;
  pair.baseline_mm = right_centre_in_left.norm();
  const Vec3 x = right_centre_in_left / pair.baseline_mm;
  // The right camera's optical axis in the left frame is R^T e_z, the third row of R.
  const Vec3 mean_axis = (Vec3::UnitZ() + R.row(2).transpose()).normalized();
  const Vec3 y = mean_axis.cross(x).normalized();
  const Vec3 z = x.cross(y);
  pair.rect_from_left.row(0) = x.transpose();
  pair.rect_from_left.row(1) = y.transpose();
  pair.rect_from_left.row(2) = z.transpose();
  // X_right = R X_left + T, and the right camera's rectified frame is the left's moved by the
  // baseline along x: rect_from_right = rect_from_left R^T.
  pair.rect_from_right = pair.rect_from_left * R.transpose();
  pair.f = 0.25 * (calibration.left.fx + calibration.left.fy + calibration.right.fx + calibration.right.fy);
  return pair;
}

namespace {

// The distorted pixel (pu, pv) of grid pixels i = first .. n - 1 of one row, whose camera rays
// are ray0 + i ray_du (NaN in pu behind the camera). kPinhole5: the 5-coefficient model's
// expressions without the model's dispatch (a loop the compiler vectorises).
template <bool kPinhole5>
__attribute__((always_inline)) inline void RowPositions(const CameraIntrinsics& camera, const Vec3& ray0,
                                                        const Vec3& ray_du, int first, int n, double* __restrict pu,
                                                        double* __restrict pv) {
  for (int i = first; i < n; ++i) {
    const double rx = ray0.x() + ray_du.x() * i, ry = ray0.y() + ray_du.y() * i, rz = ray0.z() + ray_du.z() * i;
    const Vec2 d = kPinhole5 ? camera::DistortPinhole5(camera.distortion, Vec2(rx / rz, ry / rz))
                             : DistortNormalized(camera.distortion, Vec2(rx / rz, ry / rz));
    // Behind the camera: NaN, which fails the bounds test of the map reads.
    pu[i] = rz > 1e-12 ? camera.fx * d.x() + camera.cx : std::numeric_limits<double>::quiet_NaN();
    pv[i] = camera.fy * d.y() + camera.cy;
  }
}

void RowPositionsBaseline(const CameraIntrinsics& camera, const Vec3& ray0, const Vec3& ray_du, int n, double* pu,
                          double* pv) {
  if (camera.distortion.model == camera::LensModel::kPinhole5) {
    RowPositions<true>(camera, ray0, ray_du, 0, n, pu, pv);
  } else {
    RowPositions<false>(camera, ray0, ray_du, 0, n, pu, pv);
  }
}

// The same on four lanes (AVX2), for the 5-coefficient model only: each lane takes the loop's
// operations in its order (no FMA target), so the positions are bit-identical; the last pixels by
// the loop itself.
RAMTK_AVX2 void RowPositionsAvx2(const CameraIntrinsics& camera, const Vec3& ray0, const Vec3& ray_du, int n,
                                 double* pu, double* pv) {
  const __m256d ox = _mm256_set1_pd(ray0.x()), oy = _mm256_set1_pd(ray0.y()), oz = _mm256_set1_pd(ray0.z());
  const __m256d sx = _mm256_set1_pd(ray_du.x()), sy = _mm256_set1_pd(ray_du.y()), sz = _mm256_set1_pd(ray_du.z());
  const __m256d nan = _mm256_set1_pd(std::numeric_limits<double>::quiet_NaN()), near = _mm256_set1_pd(1e-12);
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m256d iv = _mm256_setr_pd(i, i + 1, i + 2, i + 3);
    const __m256d rx = _mm256_add_pd(ox, _mm256_mul_pd(sx, iv)), ry = _mm256_add_pd(oy, _mm256_mul_pd(sy, iv)),
                  rz = _mm256_add_pd(oz, _mm256_mul_pd(sz, iv));
    __m256d r2, radial, ux, uy;
    DistortNormalized4(camera.distortion, _mm256_div_pd(rx, rz), _mm256_div_pd(ry, rz), &r2, &radial, &ux, &uy);
    const __m256d u = _mm256_add_pd(_mm256_mul_pd(_mm256_set1_pd(camera.fx), ux), _mm256_set1_pd(camera.cx));
    _mm256_storeu_pd(pu + i, _mm256_blendv_pd(nan, u, _mm256_cmp_pd(rz, near, _CMP_GT_OQ)));
    _mm256_storeu_pd(pv + i, _mm256_add_pd(_mm256_mul_pd(_mm256_set1_pd(camera.fy), uy), _mm256_set1_pd(camera.cy)));
  }
  RowPositions<true>(camera, ray0, ray_du, i, n, pu, pv);
}

// The map's bilinear value at grid pixels [i, n) of a row (their distorted positions pu, pv),
// NaN off the valid box or in a cell that is not valid, four pixels at a time on AVX2 lanes with
// the scalar loop's operations in its order; returns the first pixel not done.
RAMTK_AVX2 int ReadRowAvx2(const double* pu, const double* pv, int n, int x0, int x1, int y0, int y1,
                           const uchar* cell_ok, int cols, const float* coord, int step, float* out) {
  const __m256d bx0 = _mm256_set1_pd(x0), bx1 = _mm256_set1_pd(x1), by0 = _mm256_set1_pd(y0), by1 = _mm256_set1_pd(y1),
                one = _mm256_set1_pd(1.0);
  const __m128 nan = _mm_set1_ps(std::numeric_limits<float>::quiet_NaN());
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m256d u = _mm256_loadu_pd(pu + i), v = _mm256_loadu_pd(pv + i);
    const __m256d inside =
        _mm256_and_pd(_mm256_and_pd(_mm256_cmp_pd(u, bx0, _CMP_GE_OQ), _mm256_cmp_pd(u, bx1, _CMP_LT_OQ)),
                      _mm256_and_pd(_mm256_cmp_pd(v, by0, _CMP_GE_OQ), _mm256_cmp_pd(v, by1, _CMP_LT_OQ)));
    int ok = _mm256_movemask_pd(inside);
    if (!ok) {
      _mm_storeu_ps(out + i, nan);
      continue;
    }
    const __m256d cu = _mm256_floor_pd(u), cv = _mm256_floor_pd(v);
    alignas(16) int iu[4], iv[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(iu), _mm256_cvttpd_epi32(_mm256_and_pd(cu, inside)));
    _mm_store_si128(reinterpret_cast<__m128i*>(iv), _mm256_cvttpd_epi32(_mm256_and_pd(cv, inside)));
    alignas(16) float c[4][4] = {};
    for (int k = 0; k < 4; ++k) {
      if (!(ok >> k & 1)) continue;
      if (!cell_ok[static_cast<std::size_t>(iv[k]) * cols + iu[k]]) {
        ok &= ~(1 << k);
        continue;
      }
      const float* c0 = coord + static_cast<std::size_t>(iv[k]) * step + iu[k];
      c[0][k] = c0[0], c[1][k] = c0[1], c[2][k] = c0[step], c[3][k] = c0[step + 1];
    }
    const __m256d fu = _mm256_sub_pd(u, cu), fv = _mm256_sub_pd(v, cv);
    const __m256d gu = _mm256_sub_pd(one, fu), gv = _mm256_sub_pd(one, fv);
    const __m256d value = _mm256_add_pd(
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_mul_pd(gu, gv), _mm256_cvtps_pd(_mm_load_ps(c[0]))),
                                    _mm256_mul_pd(_mm256_mul_pd(fu, gv), _mm256_cvtps_pd(_mm_load_ps(c[1])))),
                      _mm256_mul_pd(_mm256_mul_pd(gu, fv), _mm256_cvtps_pd(_mm_load_ps(c[2])))),
        _mm256_mul_pd(_mm256_mul_pd(fu, fv), _mm256_cvtps_pd(_mm_load_ps(c[3]))));
    const __m128 valid =
        _mm_castsi128_ps(_mm_setr_epi32(-(ok & 1), -((ok >> 1) & 1), -((ok >> 2) & 1), -((ok >> 3) & 1)));
    _mm_storeu_ps(out + i, _mm_blendv_ps(nan, _mm256_cvtpd_ps(value), valid));
  }
  return i;
}

}  // namespace

RectifiedGrid ResampleOnRectifiedGrid(const CameraIntrinsics& camera, const Mat3& rect_from_camera, double f,
                                      const cv::Mat& coord, const std::vector<uchar>& cell_ok, double max_pixels) {
  RectifiedGrid grid;
  const int cols = coord.cols, rows = coord.rows;
  // The valid cells' bounding box (cell x spans pixels x .. x + 1).
  int x0 = cols, x1 = -1, y0 = rows, y1 = -1;
  for (int y = 0; y + 1 < rows; ++y) {
    const uchar* ok = cell_ok.data() + static_cast<std::size_t>(y) * cols;
    const uchar* first = std::find(ok, ok + cols - 1, uchar{1});
    if (first == ok + cols - 1) continue;
    int last = cols - 2;
    while (!ok[last]) --last;
    x0 = std::min(x0, static_cast<int>(first - ok));
    x1 = std::max(x1, last + 1);
    y0 = std::min(y0, y);
    y1 = y + 1;
  }
  if (x1 < 0) return grid;
  // Its rectified image: bounded by the image of its border (the map is one-to-one).
  double u_lo = 1e300, u_hi = -1e300, v_lo = 1e300, v_hi = -1e300;
  bool usable = true;  // false if a border ray points behind the rectified frame (or is NaN)
  auto add = [&](double u, double v) {
    const Vec2 ideal =
        UndistortNormalized(camera.distortion, Vec2((u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy));
    const Vec3 r = rect_from_camera * Vec3(ideal.x(), ideal.y(), 1.0);
    if (!(r.z() > 1e-9 && std::isfinite(r.x()) && std::isfinite(r.y()))) {
      usable = false;
      return;
    }
    u_lo = std::min(u_lo, f * r.x() / r.z()), u_hi = std::max(u_hi, f * r.x() / r.z());
    v_lo = std::min(v_lo, f * r.y() / r.z()), v_hi = std::max(v_hi, f * r.y() / r.z());
  };
  for (int k = 0; k <= 64; ++k) {
    const double u = x0 + (x1 - x0) * k / 64.0, v = y0 + (y1 - y0) * k / 64.0;
    add(u, y0), add(u, y1), add(x0, v), add(x1, v);
  }
  const double width = u_hi - u_lo + 5, height = v_hi - v_lo + 5;
  // The bounds also keep the grid's integer origin and size far inside int.
  if (!usable || !(width > 0 && height > 0 && width * height <= max_pixels) || !(std::abs(u_lo) < 1e8) ||
      !(std::abs(v_lo) < 1e8) || !(std::abs(u_hi) < 1e8) || !(std::abs(v_hi) < 1e8))
    return grid;
  grid.u0 = static_cast<int>(std::floor(u_lo)) - 2;
  grid.v0 = static_cast<int>(std::floor(v_lo)) - 2;
  const int gcols = static_cast<int>(std::ceil(u_hi)) + 2 - grid.u0 + 1;
  const int grows = static_cast<int>(std::ceil(v_hi)) + 2 - grid.v0 + 1;
  grid.coord.create(grows, gcols, CV_32F);
  grid.row_min.assign(grows, std::numeric_limits<float>::infinity());
  grid.row_max.assign(grows, -std::numeric_limits<float>::infinity());
  grid.blocks = (gcols - 1 + RectifiedGrid::kBlock - 1) / RectifiedGrid::kBlock;
  grid.block_min.assign(static_cast<std::size_t>(grid.blocks) * grows, std::numeric_limits<float>::infinity());
  grid.block_max.assign(grid.block_min.size(), -std::numeric_limits<float>::infinity());
  const Mat3 camera_from_rect = rect_from_camera.transpose();
  const Vec3 ray_du = camera_from_rect.col(0) / f;
  const bool avx2 = Avx2Kernels();
  const bool avx2_positions = avx2 && camera.distortion.model == camera::LensModel::kPinhole5;
  tbb::parallel_for(tbb::blocked_range<int>(0, grows, 8), [&](const tbb::blocked_range<int>& range) {
    // Each row in two loops: the distorted positions (arithmetic only, which the compiler
    // vectorises), then the reads of the map (gathers and branches).
    std::vector<double> pu(static_cast<std::size_t>(gcols)), pv(static_cast<std::size_t>(gcols));
    for (int j = range.begin(); j < range.end(); ++j) {
      const Vec3 ray0 = camera_from_rect * Vec3(grid.u0 / f, (grid.v0 + j) / f, 1.0);
      (avx2_positions ? RowPositionsAvx2 : RowPositionsBaseline)(camera, ray0, ray_du, gcols, pu.data(), pv.data());
      float* out = grid.coord.ptr<float>(j);
      float lo = std::numeric_limits<float>::infinity(), hi = -lo;
      int start = 0;
      if (avx2) {
        start = ReadRowAvx2(pu.data(), pv.data(), gcols, x0, x1, y0, y1, cell_ok.data(), cols, coord.ptr<float>(),
                            static_cast<int>(coord.step1()), out);
        for (int i = 0; i < start; ++i) lo = std::min(lo, out[i]), hi = std::max(hi, out[i]);  // NaNs drop out
      }
      for (int i = start; i < gcols; ++i) {
        const double u = pu[i], v = pv[i];
        out[i] = std::numeric_limits<float>::quiet_NaN();
        if (!(u >= x0 && u < x1 && v >= y0 && v < y1)) continue;
        const int cu = FloorToInt(u), cv = FloorToInt(v);
        if (!cell_ok[static_cast<std::size_t>(cv) * cols + cu]) continue;
        const float* c0 = coord.ptr<float>(cv) + cu;
        const float* c1 = coord.ptr<float>(cv + 1) + cu;
        const double fu = u - cu, fv = v - cv;
        const double value =
            (1 - fu) * (1 - fv) * c0[0] + fu * (1 - fv) * c0[1] + (1 - fu) * fv * c1[0] + fu * fv * c1[1];
        out[i] = static_cast<float>(value);
        lo = std::min(lo, out[i]), hi = std::max(hi, out[i]);
      }
      grid.row_min[j] = lo;
      grid.row_max[j] = hi;
      float* block_lo = grid.block_min.data() + static_cast<std::size_t>(j) * grid.blocks;
      float* block_hi = grid.block_max.data() + static_cast<std::size_t>(j) * grid.blocks;
      for (int b = 0; b < grid.blocks; ++b) {
        const int end = std::min(gcols - 1, (b + 1) * RectifiedGrid::kBlock);
        for (int i = b * RectifiedGrid::kBlock; i <= end; ++i)  // NaNs drop out of min / max
          block_lo[b] = std::min(block_lo[b], out[i]), block_hi[b] = std::max(block_hi[b], out[i]);
      }
    }
  });
  return grid;
}

}  // namespace ramtk::vision::detail
