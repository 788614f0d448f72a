#pragma once
// How many lattice points fit along a side, shared by lattice() (src/core/lattice.hpp) and the
// scene checks (src/scene.cpp), which must count without Kokkos.
#include <cmath>

namespace dvisph {

inline double lattice_sites(double side, double dx) { return std::floor(side / dx + 1e-9); }

}  // namespace dvisph
