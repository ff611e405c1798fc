// Independent cross-laser device log generator (issue 15). See README.md.
#pragma once

#include "common.h"

namespace indep {

void GenerateLaser(const GenOptions& options);

}  // namespace indep
