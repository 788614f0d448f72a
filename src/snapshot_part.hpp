#pragma once
// One particle set's share of a snapshot (positions, kinds, fields), on the host; a
// simulation with water and beads writes both sets into one snapshot (simulation.hpp).
#include "src/snapshot_writer.hpp"

#include <vector>

namespace dvisph {

struct SnapshotPart {
  std::vector<double> x;  // n x D
  std::vector<int> kind;
  std::vector<SnapshotField> fields;
};

}  // namespace dvisph
