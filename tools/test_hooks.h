#pragma once
// The library's comparison switches (vision's detail::DecodeTestHooks and
// detail::StereoMatchTestHooks) for the command line. They are no option of any command: the
// environment variable RAMTK_TEST_HOOKS holds a comma-separated list of
//   reference_decode  the reference decode (float frames, one pass per stage over every pixel)
//   full_search       every pixel matched by the whole-range search, not walked from a neighbour
//   curve_back_pass   the left-right check's back pass along the distorted curves, not rectified rows
// for tests and benchmarks that compare a command's results with a reference.

namespace ramtk::tools {

struct TestHooks {
  bool reference_decode = false;  // DecodeTestHooks::reference_path
  bool full_search = false;       // StereoMatchTestHooks::full_search
  bool curve_back_pass = false;   // StereoMatchTestHooks::rectified_back_pass off
};

// Reads RAMTK_TEST_HOOKS (unset or empty: none) and sets the library's hooks for the rest of the
// process. An unknown name is an InputError naming the variable and the known names.
TestHooks ApplyTestHooksFromEnvironment();

}  // namespace ramtk::tools
