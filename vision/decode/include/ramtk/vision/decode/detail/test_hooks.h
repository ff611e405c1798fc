#pragma once
// Comparison switches of the decode. Each selects the reference implementation a production path
// is tested against; none is part of DecodeOptions. They are process-wide and read at the start
// of each decode: tests and benchmarks set them with ScopedDecodeTestHooks, the command line from
// RAMTK_TEST_HOOKS (tools/test_hooks.cpp). Production code never sets them.

namespace ramtk::vision::detail {

struct DecodeTestHooks {
  // The reference decode (decode_reference.cpp: separate passes over float copies of the frames,
  // every pixel) in place of the fused path (decode_fused.cpp). Both give the same phase, mask and
  // coordinate within float rounding (tests/vision/decode_fast_test.cpp). The fused path differs
  // only in (a) `wrapped` is 0 where a pixel is masked by darkness, saturation or modulation,
  // (b) edge_corrections counts unmasked pixels only, (c) the harmonic ratios are averaged over
  // every harmonic_stride-th pixel. Frames are then loaded as float.
  bool reference_path = false;
};

DecodeTestHooks CurrentDecodeTestHooks();
void SetDecodeTestHooks(const DecodeTestHooks& hooks);

// Sets the hooks for its lifetime and restores the previous ones after.
class ScopedDecodeTestHooks {
 public:
  explicit ScopedDecodeTestHooks(const DecodeTestHooks& hooks) : saved_(CurrentDecodeTestHooks()) {
    SetDecodeTestHooks(hooks);
  }
  ~ScopedDecodeTestHooks() { SetDecodeTestHooks(saved_); }
  ScopedDecodeTestHooks(const ScopedDecodeTestHooks&) = delete;
  ScopedDecodeTestHooks& operator=(const ScopedDecodeTestHooks&) = delete;

 private:
  DecodeTestHooks saved_;
};

}  // namespace ramtk::vision::detail
