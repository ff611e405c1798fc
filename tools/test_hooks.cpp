#include "test_hooks.h"

#include <cstdlib>
#include <sstream>
#include <string>

#include "ramtk/core/error.h"
#include "ramtk/vision/decode/detail/test_hooks.h"
#include "ramtk/vision/stereo/detail/test_hooks.h"

namespace ramtk::tools {

TestHooks ApplyTestHooksFromEnvironment() {
  TestHooks hooks;
  const char* value = std::getenv("RAMTK_TEST_HOOKS");
  std::istringstream list(value ? value : "");
  for (std::string name; std::getline(list, name, ',');) {
    if (name == "reference_decode")
      hooks.reference_decode = true;
    else if (name == "full_search")
      hooks.full_search = true;
    else if (name == "curve_back_pass")
      hooks.curve_back_pass = true;
    else if (!name.empty())
      throw InputError({"", 0, "RAMTK_TEST_HOOKS"},
                       "unknown hook '" + name + "' (known: reference_decode, full_search, curve_back_pass)");
  }
  vision::detail::DecodeTestHooks decode;
  decode.reference_path = hooks.reference_decode;
  vision::detail::SetDecodeTestHooks(decode);
  vision::detail::StereoMatchTestHooks match;
  match.full_search = hooks.full_search;
  match.rectified_back_pass = !hooks.curve_back_pass;
  vision::detail::SetStereoMatchTestHooks(match);
  return hooks;
}

}  // namespace ramtk::tools
