#pragma once
// The backend a test executable was compiled for (set by tests/CMakeLists.txt).
#include <Kokkos_Core.hpp>

#ifndef DVISPH_TEST_SPACE
#define DVISPH_TEST_SPACE Kokkos::DefaultExecutionSpace
#endif
using TestSpace = DVISPH_TEST_SPACE;
