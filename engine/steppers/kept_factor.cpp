#include "engine/steppers/kept_factor.h"

#include <limits>

namespace csim {

bool rows_hold(const HeldRows& rows, bool hub) {
  bool sticking = false;
  for (const auto& row : rows) sticking = sticking || row.second == Hold::stick;
  return !rows.empty() && (!hub || sticking);
}

void KeptFactor::record(Made made) {
  made_ = std::move(made);
  valid_ = true;
}

void KeptFactor::observe(double increment, bool kept, bool whole_step) {
  increment_before_ = increment_;
  increment_ = increment;
  whole_before_ = whole_;
  whole_ = whole_step;
  kept_before_ = last_kept_;
  last_kept_ = kept;
}

double KeptFactor::distance_bound() const {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  if (!valid_ || !last_kept_ || !kept_before_ || !whole_ || !whole_before_ || !(increment_before_ > 0.0)) return kNone;
  const double theta = increment_ / increment_before_;
  return theta <= kContraction ? theta / (1.0 - theta) * increment_ : kNone;
}

bool KeptFactor::fits(const HeldRows& rows, double held_weight, double hub_proximal, bool hub) const {
  if (!valid_) return false;
  if (last_kept_ && increment_ > kContraction * increment_before_) return false;
  switch (made_.kind) {
    case Kind::stiffness: return true;
    case Kind::held: return held_weight == made_.held_weight && rows == made_.rows;
    case Kind::proximal: return hub_proximal == made_.hub_proximal && !rows_hold(rows, hub);
  }
  return false;
}

}  // namespace csim
