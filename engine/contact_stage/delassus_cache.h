// The Delassus operator W = H A⁻¹ Hᵀ of rows that persist from step to step, kept by the rows'
// identity while A's factorization stays (a finite-element World's constant iteration matrix): a node
// resting or sliding on a surface keeps its contact rows, and a prescription or a linear constraint
// its row, so that a step recomputes the entries of W of the rows that entered or changed only.
//
// Each row h keeps its forward column y = L⁻¹ P hᵀ (sparse_ldlt.h: the union of its nonzeros' paths to
// the root of the elimination tree, a small part of the n entries of A⁻¹ hᵀ) and a slot; W between
// slots is W(a, b) = y_aᵀ D⁻¹ y_b, computed when a row enters, symmetric exactly. A step costs the
// look-ups and the new rows' forward columns and entries, O(rows × reach) each, not a solve per row.
#pragma once

#include "contact/contact_point.h"
#include "engine/linear_algebra/sparse_ldlt.h"

#include <compare>
#include <map>
#include <vector>

namespace csim {

class DelassusCache {
 public:
  // A row's identity: a contact's k-th row, an equality's row e, a tie's row (kind tells which).
  struct Key {
    int kind = 0;
    ContactKey contact;
    int row = 0;
    auto operator<=>(const Key&) const = default;
  };

  // Starts an assembly; everything is dropped when the factor was refactored since the last one.
  void begin(const SparseLdlt& factor);
  // The slot of the row h = Σ_k value[k] e_{index[k]}ᵀ of this identity; its forward column is
  // recomputed when the row is new or differs from the one kept.
  int slot(const Key& key, const int* index, const double* value, int count);
  // Frees the rows not asked for since begin, and computes the entries of W of the new rows.
  void finish();
  // Computes the entries of W of the rows that entered or changed since their entries were last
  // computed: before operator() is asked. A user that takes only the forward columns
  // (a sparse W, block_gram.h) never pays for the dense entries.
  void compute_entries();
  double operator()(int slot_a, int slot_b) const { return delassus_(slot_a, slot_b); }
  // The forward column L⁻¹ P hᵀ of the row in this slot (asked for since begin).
  const SparseLdlt::ForwardColumn& forward(int slot) const { return by_slot_[slot]->forward; }
  std::size_t rows() const { return entries_.size(); }
  std::size_t stored_values() const;  // entries of the forward columns kept, for the memory budget
  Eigen::Index dense_capacity() const { return delassus_.rows(); }  // W's dense storage: slots it can hold
  long computed_entries() const { return computed_entries_; }  // entries of W computed so far

  // What a user took from the cache for a list of slots (a copy of W, their forward columns stored
  // elsewhere): the slots, and how many forward columns had been computed then. The same slots with no
  // forward column computed since (a row that changes is computed again) hold the same forward columns
  // and, once compute_entries has run, the same entries.
  struct Taken {
    std::vector<int> slots;
    long changes = -1;
  };
  // Whether `taken` still holds for these slots; when not, it is set to them (the caller then takes
  // them again).
  bool still_holds(Taken& taken, const std::vector<int>& slots) const;

 private:
  struct Entry {
    std::vector<int> index;
    std::vector<double> value;
    SparseLdlt::ForwardColumn forward;
    int slot = -1;
    bool used = false;
    bool stale = true;  // its entries of W are still to compute (compute_entries)
  };
  const SparseLdlt* factor_ = nullptr;
  long factorization_ = -1;
  std::map<Key, Entry> entries_;
  std::vector<Entry*> fresh_;     // compute_entries' work list: the stale rows
  std::vector<const Entry*> by_slot_;
  std::vector<int> free_slots_;
  int slot_count_ = 0;
  Matrix delassus_;               // slots × slots
  Vector scattered_;              // a fresh row's forward column, dense (the factor's order)
  long computed_entries_ = 0;
  long changes_ = 0;              // forward columns computed so far (still_holds)
};

}  // namespace csim
