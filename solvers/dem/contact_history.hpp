#pragma once
// Tangential contact history keyed by partner: for each particle, a fixed-capacity list
// of its current partners (by stable id; wall w as -(w + 1)) with the tangential
// displacement of each contact. Each particle of a pair holds its own copy (the two are
// exact opposites). The step keeps the history at the listed pairs (pair_contacts.hpp);
// this form is what survives a new list, a reorder (rows follow the particles, partners
// are found by id) and a checkpoint. A contact that does not fit is counted; the solver
// reports the count as an error.
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

    // Slot of particle i's contact with `p`, -1 if none.
    KOKKOS_INLINE_FUNCTION int find(int i, int p) const {
      for (int s = 0; s < count(i); ++s)
        if (partner(i, s) == p) return s;
      return -1;
    }
  };

  // Fills one particle's row.
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
  };

  ContactHistory() = default;
  ContactHistory(int n, int capacity)
      : capacity_(capacity),
        table_("dvisph::dem::history", n, capacity),
        overflow_("dvisph::dem::history::overflow") {}

  int capacity() const { return capacity_; }
  const Table& table() const { return table_; }
  Writer writer() const { return {table_, overflow_, capacity_}; }

  // Contacts dropped for lack of room since construction.
  int overflows() const {
    int h = 0;
    Kokkos::deep_copy(h, overflow_);
    return h;
  }

  void save(Checkpoint& c, const std::string& prefix) const {
    c.put(prefix + "count", table_.count);
    c.put(prefix + "partner", table_.partner);
    c.put(prefix + "xi", table_.xi);
  }
  void restore(const Checkpoint& c, const std::string& prefix) {
    c.get(prefix + "count", table_.count);
    c.get(prefix + "partner", table_.partner);
    c.get(prefix + "xi", table_.xi);
  }

  // Row perm(a) becomes row a, as the particles are reordered.
  template <class Perm>
  void permute(const Perm& perm) {
    const int n = static_cast<int>(perm.extent(0));
    const Table in = table_, out("dvisph::dem::history::permuted", n, capacity_);
    Kokkos::parallel_for(
        "dvisph::dem::history::permute", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int a) {
          const int i = perm(a);
          out.count(a) = in.count(i);
          for (int s = 0; s < in.count(i); ++s) {
            out.partner(a, s) = in.partner(i, s);
            for (int k = 0; k < D; ++k) out.xi(a, s, k) = in.xi(i, s, k);
          }
        });
    table_ = out;
  }

 private:
  int capacity_ = 0;
  Table table_;
  Kokkos::View<int, memory_space> overflow_;
};

}  // namespace dvisph::dem
