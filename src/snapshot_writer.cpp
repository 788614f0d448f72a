#include "src/snapshot_writer.hpp"

#include "src/hdf5_setup.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace dvisph {
namespace {

void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5: " + what);
}

template <class T>
void write_dataset(hid_t file, const std::string& name, hid_t type, const T* data, hsize_t rows,
                   hsize_t cols, const std::string& path) {
  const hsize_t dims[2] = {rows, cols};
  const hid_t space = H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr);
  const hid_t set = H5Dcreate2(file, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (set < 0) {
    H5Sclose(space);
    throw std::runtime_error(fmt::format("cannot create dataset {} in {}", name, path));
  }
  const herr_t status = H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  H5Dclose(set);
  H5Sclose(space);
  check(status, fmt::format("cannot write dataset {} in {}", name, path));
}

}  // namespace

void SnapshotWriter::write(double t, int dim, const std::vector<double>& x,
                           const std::vector<SnapshotField>& fields, const std::vector<int>& kind) {
  const long n = static_cast<long>(kind.size());
  const std::string name = fmt::format("snapshot_{:05d}.h5", count());
  const std::string path = dir_ + "/" + name;
  const std::string tmp = path + ".tmp";
  prepare_hdf5();
  const hid_t file = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error(fmt::format("cannot create {}", tmp));
  try {
    write_dataset(file, "x", H5T_NATIVE_DOUBLE, x.data(), n, dim, tmp);
    write_dataset(file, "kind", H5T_NATIVE_INT, kind.data(), n, 1, tmp);
    for (const auto& f : fields)
      write_dataset(file, f.name, H5T_NATIVE_DOUBLE, f.values.data(), n, f.components, tmp);
    const hsize_t one = 1;
    const hid_t space = H5Screate_simple(1, &one, nullptr);
    const hid_t attr = H5Acreate2(file, "time", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
    check(H5Awrite(attr, H5T_NATIVE_DOUBLE, &t), "cannot write time attribute in " + tmp);
    H5Aclose(attr);
    H5Sclose(space);
  } catch (...) {
    H5Fclose(file);
    std::remove(tmp.c_str());
    throw;
  }
  if (H5Fclose(file) < 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error(fmt::format("cannot close {} (disk full?)", tmp));
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error(fmt::format("cannot rename {} to {}: {}", tmp, path, ec.message()));
  std::string grid = fmt::format(
      "<Grid Name=\"{}\" GridType=\"Uniform\">\n<Time Value=\"{:.9g}\"/>\n"
      "<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\"/>\n"
      "<Geometry GeometryType=\"{}\">\n<DataItem Dimensions=\"{} {}\" NumberType=\"Float\" "
      "Precision=\"8\" Format=\"HDF\">{}:/x</DataItem>\n</Geometry>\n",
      name, t, n, dim == 2 ? "XY" : "XYZ", n, dim, name);
  auto attribute = [&](const std::string& field, int c, bool is_int) {
    grid += fmt::format("<Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">\n<DataItem "
                        "Dimensions=\"{}{}\" NumberType=\"{}\" Precision=\"{}\" Format=\"HDF\">{}:/{}"
                        "</DataItem>\n</Attribute>\n",
                        field, c == 1 ? "Scalar" : "Vector", n, c == 1 ? "" : fmt::format(" {}", c),
                        is_int ? "Int" : "Float", is_int ? 4 : 8, name, field);
  };
  for (const auto& f : fields) attribute(f.name, f.components, false);
  attribute("kind", 1, true);
  index_.push_back(grid + "</Grid>\n");
  write_index();
}

void SnapshotWriter::write_index() const {
  const std::string path = dir_ + "/snapshots.xdmf", tmp = path + ".tmp";
  // std::ofstream, not fmt::output_file: fmt's file flushes in its destructor and
  // terminates the program when that write fails (disk full)
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
           "<Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (const auto& grid : index_) out << grid;
    out << "</Grid>\n</Domain>\n</Xdmf>\n";
    if (!out.flush()) {
      std::remove(tmp.c_str());
      throw std::runtime_error(fmt::format("cannot write {} (disk full?)", tmp));
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error(fmt::format("cannot write {}: {}", path, ec.message()));
}

}  // namespace dvisph
