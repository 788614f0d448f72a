#pragma once
#include <stdexcept>

namespace dvisph {

// A run that cannot go on (exit code 3): NaN, a particle out of the domain, CG not
// converged, beads overlapping too deep. The message names the particle, the step and
// the quantity.
struct NumericalError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace dvisph
