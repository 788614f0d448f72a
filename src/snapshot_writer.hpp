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
  int count() const { return static_cast<int>(index_.size()); }
  // The XDMF entries so far; a restarted run resumes from them and numbers on.
  const std::vector<std::string>& index() const { return index_; }
  void resume(std::vector<std::string> index) { index_ = std::move(index); }

 private:
  void write_index() const;
  std::string dir_;
  std::vector<std::string> index_;  // one XDMF grid per snapshot
};

}  // namespace dvisph
