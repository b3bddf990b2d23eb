#include "engine/contact_stage/delassus_cache.h"

#include <algorithm>

namespace csim {

bool DelassusCache::still_holds(Taken& taken, const std::vector<int>& slots) const {
  if (taken.slots == slots && taken.changes == changes_) return true;
  taken.slots = slots;
  taken.changes = changes_;
  return false;
}

void DelassusCache::begin(const SparseLdlt& factor) {
  if (&factor != factor_ || factor.factorizations() != factorization_) {
    entries_.clear();
    free_slots_.clear();
    slot_count_ = 0;
    factor_ = &factor;
    factorization_ = factor.factorizations();
  }
  for (auto& [key, entry] : entries_) entry.used = false;
}

int DelassusCache::slot(const Key& key, const int* index, const double* value, int count) {
  Entry& entry = entries_[key];
  entry.used = true;
  const bool same = entry.slot >= 0 && static_cast<int>(entry.index.size()) == count &&
                    std::equal(index, index + count, entry.index.begin()) &&
                    std::equal(value, value + count, entry.value.begin());
  if (same) return entry.slot;
  entry.index.assign(index, index + count);
  entry.value.assign(value, value + count);
  factor_->forward(index, value, count, entry.forward);
  ++changes_;
  if (entry.slot < 0) {
    if (free_slots_.empty()) {
      entry.slot = slot_count_++;
    } else {
      entry.slot = free_slots_.back();
      free_slots_.pop_back();
    }
  }
  if (static_cast<int>(by_slot_.size()) < slot_count_) by_slot_.resize(slot_count_);
  by_slot_[entry.slot] = &entry;
  entry.stale = true;
  return entry.slot;
}

void DelassusCache::finish() {
  for (auto it = entries_.begin(); it != entries_.end();) {
    if (it->second.used) {
      ++it;
      continue;
    }
    if (it->second.slot >= 0) free_slots_.push_back(it->second.slot);
    it = entries_.erase(it);
  }
}

void DelassusCache::compute_entries() {
  fresh_.clear();
  for (auto& [key, entry] : entries_)
    if (entry.stale) fresh_.push_back(&entry);
  if (fresh_.empty()) return;
  // W's dense storage grows here, not with the slots: a user of the forward columns alone (a sparse W)
  // never holds slots² doubles (1000 dropped spheres: 3000 slots, 290 MB at a doubled capacity).
  if (slot_count_ > delassus_.rows()) {
    const int capacity = std::max(16, 2 * slot_count_);
    delassus_.conservativeResize(capacity, capacity);
  }
  // Each fresh row against every row kept: its forward column scaled by D⁻¹ and scattered once, then
  // one sparse dot product per row, stored on both sides (W symmetric exactly). A pair of fresh rows is
  // computed once, by the later of the two.
  std::vector<char> done(slot_count_, 0);
  for (const auto& [key, entry] : entries_) done[entry.slot] = 1;
  for (const Entry* fresh : fresh_) done[fresh->slot] = 0;
  scattered_.setZero(factor_->size());
  for (Entry* fresh : fresh_) {
    const SparseLdlt::ForwardColumn& y = fresh->forward;
    factor_->scatter_scaled(y, scattered_);
    done[fresh->slot] = 1;
    for (const auto& [key, other] : entries_) {
      if (!done[other.slot]) continue;  // a fresh row still to come computes this pair
      const double w = SparseLdlt::dot(other.forward, scattered_);
      delassus_(fresh->slot, other.slot) = w;
      delassus_(other.slot, fresh->slot) = w;
      ++computed_entries_;
    }
    for (int i : y.index) scattered_(i) = 0.0;
    fresh->stale = false;
  }
}

std::size_t DelassusCache::stored_values() const {
  std::size_t count = 0;
  for (const auto& [key, entry] : entries_) count += entry.forward.index.size();
  return count;
}

}  // namespace csim
