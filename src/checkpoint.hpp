#pragma once
// Checkpoints: the whole state of a run in one HDF5 file, enough to continue it
// bit-identically (`dvisph run --restart`). The file is written under a temporary name
// and renamed over the old one, so a run killed at any moment leaves the previous
// checkpoint or the new one, never a half-written file.
#include "src/core/types.hpp"

#include <map>
#include <stdexcept>
#include <type_traits>
#include <string>
#include <vector>

namespace dvisph {

class Checkpoint {
 public:
  // Arrays are stored row-major with their extents; ints and reals apart.
  template <class T>
  struct Array {
    std::vector<std::size_t> extents;
    std::vector<T> values;
  };

  void set(const std::string& name, double value) { numbers_[name] = value; }
  void set_text(const std::string& name, const std::string& value) { texts_[name] = value; }
  double number(const std::string& name) const;
  const std::string& text(const std::string& name) const;
  bool has(const std::string& name) const {
    return numbers_.count(name) || reals_.count(name) || ints_.count(name) || texts_.count(name);
  }

  // Any Kokkos view of rank 1 to 3 (any layout, any memory space), element by element.
  template <class View>
  void put(const std::string& name, const View& view);
  // Into a view of the stored extents; throws naming the array if they differ.
  template <class View>
  void get(const std::string& name, const View& view) const;
  std::vector<std::size_t> extents(const std::string& name) const;
  // The stored values of an array, row-major.
  template <class T>
  const auto& values(const std::string& name) const {
    const auto& t = table<std::remove_const_t<T>>(*this);
    const auto it = t.find(name);
    if (it == t.end()) throw std::runtime_error("checkpoint: no array '" + name + "'");
    return it->second.values;
  }

  // Throws std::runtime_error naming the file (unwritable, disk full, not a checkpoint).
  void write(const std::string& path) const;
  static Checkpoint read(const std::string& path);

 private:
  template <class T>
  static auto& table(Checkpoint& c) {
    if constexpr (std::is_integral_v<T> || std::is_enum_v<T>) return c.ints_; else return c.reals_;
  }
  template <class T>
  static const auto& table(const Checkpoint& c) {
    if constexpr (std::is_integral_v<T> || std::is_enum_v<T>) return c.ints_; else return c.reals_;
  }
  std::map<std::string, double> numbers_;
  std::map<std::string, std::string> texts_;
  std::map<std::string, Array<double>> reals_;
  std::map<std::string, Array<long long>> ints_;
};

namespace detail {
template <class HostView, class F>
void for_each_element(const HostView& h, F&& f) {
  constexpr int rank = static_cast<int>(HostView::rank);
  static_assert(rank >= 1 && rank <= 3, "checkpoint arrays have rank 1 to 3");
  const std::size_t n0 = h.extent(0), n1 = h.extent(1), n2 = h.extent(2);
  std::size_t k = 0;
  for (std::size_t i = 0; i < n0; ++i)
    for (std::size_t j = 0; j < (rank > 1 ? n1 : 1); ++j)
      for (std::size_t l = 0; l < (rank > 2 ? n2 : 1); ++l, ++k) {
        if constexpr (rank == 1) f(h(i), k);
        else if constexpr (rank == 2) f(h(i, j), k);
        else f(h(i, j, l), k);
      }
}

// A LayoutRight array shaped like `view`, on its space: the state arrays are subviews
// (rows in use), possibly strided, and Kokkos copies between spaces only contiguous
// views of one layout, so checkpoints go through this.
template <class View>
auto dense_like(const View& view) {
  using Dense = Kokkos::View<typename View::traits::non_const_data_type, Kokkos::LayoutRight,
                             typename View::memory_space>;
  typename Dense::array_layout layout;
  for (int r = 0; r < static_cast<int>(View::rank); ++r) layout.dimension[r] = view.extent(r);
  return Dense(Kokkos::view_alloc(Kokkos::WithoutInitializing, view.label()), layout);
}
}  // namespace detail

template <class View>
void Checkpoint::put(const std::string& name, const View& view) {
  using T = std::remove_const_t<typename View::value_type>;
  const auto dense = detail::dense_like(view);
  Kokkos::deep_copy(dense, view);
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dense);
  auto& a = table<T>(*this)[name];
  a.extents.clear();
  for (int r = 0; r < static_cast<int>(View::rank); ++r) a.extents.push_back(view.extent(r));
  a.values.assign(h.size(), 0);
  using Stored = typename decltype(a.values)::value_type;
  detail::for_each_element(h, [&](const T& v, std::size_t k) { a.values[k] = static_cast<Stored>(v); });
}

template <class View>
void Checkpoint::get(const std::string& name, const View& view) const {
  using T = typename View::value_type;
  const auto& t = table<T>(*this);
  const auto it = t.find(name);
  if (it == t.end()) throw std::runtime_error("checkpoint: no array '" + name + "'");
  for (int r = 0; r < static_cast<int>(View::rank); ++r)
    if (r >= static_cast<int>(it->second.extents.size()) ||
        it->second.extents[r] != view.extent(r))
      throw std::runtime_error("checkpoint: array '" + name + "' has other extents than expected");
  const auto dense = detail::dense_like(view);
  auto h = Kokkos::create_mirror_view(dense);
  detail::for_each_element(h, [&](T& v, std::size_t k) { v = static_cast<T>(it->second.values[k]); });
  Kokkos::deep_copy(dense, h);
  Kokkos::deep_copy(view, dense);
}

}  // namespace dvisph
