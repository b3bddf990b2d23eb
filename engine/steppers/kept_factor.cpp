#include "engine/steppers/kept_factor.h"

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

void KeptFactor::observe(double increment, bool kept) {
  increment_before_ = increment_;
  increment_ = increment;
  last_kept_ = kept;
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
