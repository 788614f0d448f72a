#include "src/checkpoint.hpp"

#include "src/hdf5_setup.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace dvisph {
namespace {

// Closes an HDF5 handle when it goes out of scope.
struct Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  ~Handle() {
    if (id >= 0) close(id);
  }
};

// Names are flat in the file ('/' would make HDF5 groups): "dem/x" is stored as "dem.x".
std::string stored_name(std::string name, char from, char to) {
  for (auto& ch : name)
    if (ch == from) ch = to;
  return name;
}

std::runtime_error failure(const std::string& what, const std::string& path) {
  return std::runtime_error(fmt::format("checkpoint {}: {}", path, what));
}

template <class T>
void write_arrays(hid_t file, const char* group_name, hid_t type,
                  const std::map<std::string, Checkpoint::Array<T>>& arrays, const std::string& path) {
  Handle group{H5Gcreate2(file, group_name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
  if (group.id < 0) throw failure(fmt::format("cannot create group {}", group_name), path);
  for (const auto& [name, a] : arrays) {
    std::vector<hsize_t> dims(a.extents.begin(), a.extents.end());
    Handle space{H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose};
    Handle set{H5Dcreate2(group.id, stored_name(name, '/', '.').c_str(), type, space.id, H5P_DEFAULT, H5P_DEFAULT,
                          H5P_DEFAULT),
               H5Dclose};
    if (set.id < 0 ||
        (!a.values.empty() && H5Dwrite(set.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, a.values.data()) < 0))
      throw failure(fmt::format("cannot write array {} (disk full?)", name), path);
  }
}

template <class T>
void read_arrays(hid_t file, const char* group_name, hid_t type,
                 std::map<std::string, Checkpoint::Array<T>>& arrays, const std::string& path) {
  Handle group{H5Gopen2(file, group_name, H5P_DEFAULT), H5Gclose};
  if (group.id < 0) throw failure(fmt::format("no group {}: not a dvisph checkpoint", group_name), path);
  // by index, not H5Literate, whose callback type differs between HDF5 1.10 and 1.12
  H5G_info_t info;
  if (H5Gget_info(group.id, &info) < 0) throw failure(fmt::format("cannot list {}", group_name), path);
  std::vector<std::string> names;
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    const ssize_t len = H5Lget_name_by_idx(group.id, ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT);
    std::string name(len > 0 ? len : 0, '\0');
    if (len <= 0 || H5Lget_name_by_idx(group.id, ".", H5_INDEX_NAME, H5_ITER_INC, k, name.data(),
                                       len + 1, H5P_DEFAULT) < 0)
      throw failure(fmt::format("cannot list {}", group_name), path);
    names.push_back(name);
  }
  for (const auto& name : names) {
    Handle set{H5Dopen2(group.id, name.c_str(), H5P_DEFAULT), H5Dclose};
    Handle space{set.id < 0 ? -1 : H5Dget_space(set.id), H5Sclose};
    const int rank = space.id < 0 ? -1 : H5Sget_simple_extent_ndims(space.id);
    if (rank < 1 || rank > 3) throw failure(fmt::format("cannot read array {}", name), path);
    std::vector<hsize_t> dims(rank);
    H5Sget_simple_extent_dims(space.id, dims.data(), nullptr);
    auto& a = arrays[stored_name(name, '.', '/')];
    a.extents.assign(dims.begin(), dims.end());
    std::size_t n = 1;
    for (auto d : dims) n *= d;
    a.values.resize(n);
    if (n > 0 && H5Dread(set.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, a.values.data()) < 0)
      throw failure(fmt::format("cannot read array {}", name), path);
  }
}

}  // namespace

double Checkpoint::number(const std::string& name) const {
  const auto it = numbers_.find(name);
  if (it == numbers_.end()) throw std::runtime_error("checkpoint: no number '" + name + "'");
  return it->second;
}

const std::string& Checkpoint::text(const std::string& name) const {
  const auto it = texts_.find(name);
  if (it == texts_.end()) throw std::runtime_error("checkpoint: no text '" + name + "'");
  return it->second;
}

std::vector<std::size_t> Checkpoint::extents(const std::string& name) const {
  if (const auto it = reals_.find(name); it != reals_.end()) return it->second.extents;
  if (const auto it = ints_.find(name); it != ints_.end()) return it->second.extents;
  throw std::runtime_error("checkpoint: no array '" + name + "'");
}

void Checkpoint::write(const std::string& path) const {
  const std::string tmp = path + ".tmp";
  prepare_hdf5();
  try {
    Handle file{H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose};
    if (file.id < 0) throw failure("cannot create " + tmp, path);
    write_arrays(file.id, "real", H5T_NATIVE_DOUBLE, reals_, path);
    write_arrays(file.id, "int", H5T_NATIVE_LLONG, ints_, path);
    std::map<std::string, Array<double>> numbers;
    for (const auto& [name, v] : numbers_) numbers[name] = {{1}, {v}};
    write_arrays(file.id, "number", H5T_NATIVE_DOUBLE, numbers, path);
    std::map<std::string, Array<char>> texts;
    for (const auto& [name, v] : texts_) texts[name] = {{v.size()}, {v.begin(), v.end()}};
    write_arrays(file.id, "text", H5T_NATIVE_CHAR, texts, path);
    if (H5Fflush(file.id, H5F_SCOPE_GLOBAL) < 0) throw failure("cannot flush (disk full?)", path);
    const hid_t id = file.id;
    file.id = -1;
    if (H5Fclose(id) < 0) throw failure("cannot close " + tmp + " (disk full?)", path);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw failure(fmt::format("cannot rename {}: {}", tmp, ec.message()), path);
}

Checkpoint Checkpoint::read(const std::string& path) {
  prepare_hdf5();
  if (!std::filesystem::exists(path)) throw failure("no such file", path);
  Handle file{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  if (file.id < 0) throw failure("not an HDF5 file", path);
  Checkpoint c;
  read_arrays(file.id, "real", H5T_NATIVE_DOUBLE, c.reals_, path);
  read_arrays(file.id, "int", H5T_NATIVE_LLONG, c.ints_, path);
  std::map<std::string, Array<double>> numbers;
  read_arrays(file.id, "number", H5T_NATIVE_DOUBLE, numbers, path);
  for (const auto& [name, a] : numbers) c.numbers_[name] = a.values.at(0);
  std::map<std::string, Array<char>> texts;
  read_arrays(file.id, "text", H5T_NATIVE_CHAR, texts, path);
  for (const auto& [name, a] : texts) c.texts_[name] = std::string(a.values.begin(), a.values.end());
  return c;
}

}  // namespace dvisph
