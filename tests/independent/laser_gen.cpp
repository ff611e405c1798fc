#include "laser_gen.h"

#include <stdexcept>

namespace indep {

void GenerateLaser(const GenOptions&) {
  throw std::runtime_error("laser: not written yet (see tests/independent/README.md)");
}

}  // namespace indep
