#pragma once
// The library's comparison switches for one call: each helper sets a hook, runs `f` and restores
// the previous hooks (vision's detail/test_hooks.h).

#include <utility>

#include "ramtk/vision/decode/detail/test_hooks.h"
#include "ramtk/vision/stereo/detail/test_hooks.h"

namespace ramtk::vision::testing {

// detail::DecodeTestHooks with reference_path = `reference`.
inline detail::DecodeTestHooks ReferenceDecodeHooks(bool reference) {
  detail::DecodeTestHooks hooks;
  hooks.reference_path = reference;
  return hooks;
}

// f() with the reference decode (DecodeTestHooks::reference_path) when `reference`.
template <class F>
auto WithReferenceDecode(bool reference, F&& f) {
  const detail::ScopedDecodeTestHooks scope(ReferenceDecodeHooks(reference));
  return std::forward<F>(f)();
}

// f() with the stereo match's hooks set to `hooks`.
template <class F>
auto WithStereoHooks(const detail::StereoMatchTestHooks& hooks, F&& f) {
  const detail::ScopedStereoMatchTestHooks scope(hooks);
  return std::forward<F>(f)();
}

}  // namespace ramtk::vision::testing
