#pragma once
// Tangential contact history on the device: for each particle, a fixed-capacity list of
// its current partners (by stable id; wall w as -(w + 1)) with the tangential
// displacement of each contact. Each particle of a pair keeps its own copy, so the force
// kernel writes only its own row (no atomics) and, the law being antisymmetric, the two
// copies stay exact opposites. The force kernel reads the list of the last step and
// writes a new one holding exactly the contacts alive now; looking partners up by id
// keeps the history right when partners change cells or the particle order changes.
// A contact that does not fit is counted; the solver reports the count as an error.
#include "src/checkpoint.hpp"
#include "src/core/types.hpp"

#include <string>
#include <utility>

namespace dvisph::dem {

template <int D, class Space>
class ContactHistory {
 public:
  using memory_space = typename Space::memory_space;

  struct Table {
    Kokkos::View<int*, memory_space> count;
    Kokkos::View<int**, memory_space> partner;
    Kokkos::View<Real** [D], memory_space> xi;

    Table() = default;
    Table(const std::string& name, int n, int capacity)
        : count(name + "::count", n),
          partner(Kokkos::view_alloc(Kokkos::WithoutInitializing, name + "::partner"), n, capacity),
          xi(Kokkos::view_alloc(Kokkos::WithoutInitializing, name + "::xi"), n, capacity) {}

    // Tangential displacement of particle i's contact with `p`; zero for a new contact.
    KOKKOS_INLINE_FUNCTION Vec<D> find(int i, int p) const {
      for (int s = 0; s < count(i); ++s)
        if (partner(i, s) == p) return slot(i, s);
      return Vec<D>::zero();
    }
    KOKKOS_INLINE_FUNCTION Vec<D> slot(int i, int s) const {
      Vec<D> r;
      for (int k = 0; k < D; ++k) r[k] = xi(i, s, k);
      return r;
    }
  };

  // Fills one particle's row of the new table in the force kernel.
  struct Writer {
    Table table;
    Kokkos::View<int, memory_space> overflow;
    int capacity;
    KOKKOS_INLINE_FUNCTION void add(int i, int& count, int p, const Vec<D>& xi) const {
      if (count == capacity) {
        Kokkos::atomic_increment(&overflow());
        return;
      }
      table.partner(i, count) = p;
      for (int k = 0; k < D; ++k) table.xi(i, count, k) = xi[k];
      ++count;
    }
    KOKKOS_INLINE_FUNCTION void close(int i, int count) const { table.count(i) = count; }
    // The count closed so far, for a row filled by two kernels.
    KOKKOS_INLINE_FUNCTION int count(int i) const { return table.count(i); }
  };

  ContactHistory() = default;
  ContactHistory(int n, int capacity)
      : capacity_(capacity),
        current_("dvisph::dem::history::a", n, capacity),
        next_("dvisph::dem::history::b", n, capacity),
        overflow_("dvisph::dem::history::overflow") {}

  int capacity() const { return capacity_; }
  const Table& current() const { return current_; }
  Writer writer() const { return {next_, overflow_, capacity_}; }
  // The table just written becomes the current one.
  void commit() { std::swap(current_, next_); }

  // Contacts dropped for lack of room since construction.
  int overflows() const {
    int h = 0;
    Kokkos::deep_copy(h, overflow_);
    return h;
  }

  // The current table (the next is rewritten before it is read).
  void save(Checkpoint& c, const std::string& prefix) const {
    c.put(prefix + "count", current_.count);
    c.put(prefix + "partner", current_.partner);
    c.put(prefix + "xi", current_.xi);
  }
  void restore(const Checkpoint& c, const std::string& prefix) {
    c.get(prefix + "count", current_.count);
    c.get(prefix + "partner", current_.partner);
    c.get(prefix + "xi", current_.xi);
  }

  // Row perm(a) of the current table becomes row a, as the particles are reordered.
  template <class Perm>
  void permute(const Perm& perm) {
    const int n = static_cast<int>(perm.extent(0));
    const Table in = current_, out("dvisph::dem::history::permuted", n, capacity_);
    Kokkos::parallel_for(
        "dvisph::dem::history::permute", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int a) {
          const int i = perm(a);
          out.count(a) = in.count(i);
          for (int s = 0; s < in.count(i); ++s) {
            out.partner(a, s) = in.partner(i, s);
            for (int k = 0; k < D; ++k) out.xi(a, s, k) = in.xi(i, s, k);
          }
        });
    current_ = out;
  }

 private:
  int capacity_ = 0;
  Table current_, next_;
  Kokkos::View<int, memory_space> overflow_;
};

}  // namespace dvisph::dem
