#pragma once
// Small timing helper: best-of-k and median wall time of a fenced Kokkos operation.
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <vector>

namespace dvisph::bench {

struct Timing {
  double median_s, min_s;
};

template <class Space, class F>
Timing time_it(F&& f, int repeats) {
  f();  // warm-up (first-touch, allocation)
  Space().fence();
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    Kokkos::Timer timer;
    f();
    Space().fence();
    t.push_back(timer.seconds());
  }
  std::sort(t.begin(), t.end());
  return {t[t.size() / 2], t.front()};
}

}  // namespace dvisph::bench
