// A sparse matrix assembled again and again from a stream of entries (row, column, value) whose
// positions repeat from one assembly to the next: a Newton iteration's tangent stiffness, whose element
// matrices, springs and hub columns come in the same order at every iterate. The first assembly
// builds the compressed column-major pattern and remembers, for each entry of the stream, its slot in
// the values array; the next ones check that each entry comes at the position it came at before (two
// integer comparisons) and scatter the values into their slots, without the sort and copies of
// setFromTriplets. A stream whose positions change (a contact coupling new nodes, an entry left out)
// builds the pattern again, from the entry where it changed.
//
// The result equals setFromTriplets' bit for bit: each slot is the sum of its entries in the order
// they came, starting from the first (0 + v = v; only a −0 entry alone would read +0).
#pragma once

#include "engine/bodies/body.h"

#include <cstddef>
#include <vector>

namespace csim {

// Whether a and b are compressed with the same pattern (sizes, column starts, rows).
bool same_pattern(const SparseMatrix& a, const SparseMatrix& b);

class SparseAssembly {
 public:
  // A new assembly: the entries follow with add, then finish.
  void begin() {
    count_ = 0;
    leading_count_ = 0;
    replay_ = patterned_;
  }
  // After begin, when the stream's first count entries come at the positions they came at in the last
  // assembly (the caller has checked them): their values arrive summed, in stream order, by slot of the
  // last pattern (slot(k)), in sums (the values array's size, zero where none of them falls), so that
  // a caller with a long repeating head of the stream does the scatter itself. add continues at entry
  // count; the result is the same as if each had been added (a pattern built again keeps their sums).
  void resume(std::size_t count, const std::vector<double>& sums);
  // The index in the values array of the stream's k-th entry, from the last finish.
  int slot(std::size_t k) const { return slot_[k]; }
  std::size_t nonzeros() const { return static_cast<std::size_t>(pattern_.nonZeros()); }
  void add(int row, int column, double value) {
    if (replay_ && count_ < row_.size() && row_[count_] == row && column_[count_] == column) {
      value_[count_++] = value;
      return;
    }
    record(row, column, value);
  }
  void add(const Triplets& entries, std::size_t from = 0) {
    for (std::size_t k = from; k < entries.size(); ++k) add(entries[k].row(), entries[k].col(), entries[k].value());
  }
  // matrix (rows × columns, compressed) ← the sum of the entries since begin. Returns true when its
  // pattern was built again (the first time, or when the positions changed); matrix keeps its storage
  // otherwise.
  bool finish(int rows, int columns, SparseMatrix& matrix);
  long patterns() const { return patterns_; }  // patterns built so far

 private:
  void record(int row, int column, double value);
  void build_pattern(int rows, int columns);

  std::vector<int> row_, column_;  // the positions of the stream's entries, in order
  std::vector<double> value_;      // this assembly's values, in the same order
  std::vector<int> slot_;          // each entry's index in the pattern's values array
  std::size_t count_ = 0;          // entries since begin
  bool patterned_ = false;         // slot_ is the pattern of row_, column_ (and rows_ × columns_)
  bool replay_ = false;            // every entry since begin came where it came before
  std::size_t leading_count_ = 0;  // resume: the first entries, summed by the caller into *leading_
  const std::vector<double>* leading_ = nullptr;
  std::vector<int> leading_slot_;  // their slots in the last pattern, when finish builds a new one
  int rows_ = 0, columns_ = 0;
  SparseMatrix pattern_;           // the pattern (values unused), to check and restore matrix's
  long patterns_ = 0;
};

}  // namespace csim
