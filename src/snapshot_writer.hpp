#pragma once
// HDF5 snapshots with an XDMF index, so ParaView opens the series as one dataset.
// Each snapshot is written to a temporary name and renamed, and the index is
// rewritten after each, so a run stopped at any moment leaves readable files.
#include <string>
#include <vector>

namespace dvisph {

struct SnapshotField {
  std::string name;
  int components;               // 1 scalar, D vector
  std::vector<double> values;   // n * components, row-major
};

class SnapshotWriter {
 public:
  explicit SnapshotWriter(std::string directory) : dir_(std::move(directory)) {}
  // Positions (n x dim) and fields; throws std::runtime_error naming the file on failure.
  void write(double t, int dim, const std::vector<double>& x, const std::vector<SnapshotField>& fields,
             const std::vector<int>& kind);
  int count() const { return static_cast<int>(entries_.size()); }

 private:
  struct Entry {
    std::string file;
    double t;
    long n;
    int dim;
    std::vector<std::pair<std::string, int>> fields;
  };
  void write_index() const;
  std::string dir_;
  std::vector<Entry> entries_;
};

}  // namespace dvisph
