#include "engine/steppers/secant_relaxation.h"

#include <algorithm>
#include <cmath>

namespace csim {

namespace {

constexpr double kMostExtrapolation = 1000.0;  // the longest extrapolated step, / Δx
constexpr double kSteadyRatio = 0.02;          // extrapolate when ρ changes by less over two iterations
constexpr double kAligned = 0.9;               // … and the two steps' cosine is above

}  // namespace

double SecantRelaxation::next(const Vector& step) {
  double relaxation = 1.0, ratio = 0.0;
  if (previous_step_.size() == step.size() && previous_step_.squaredNorm() > 0.0 && step.squaredNorm() > 0.0) {
    const double product = step.dot(previous_step_);
    ratio = product / previous_step_.squaredNorm();
    const double cosine = product / (step.norm() * previous_step_.norm());
    const bool steady = std::abs(ratio - previous_ratio_) < kSteadyRatio;
    if (ratio < -0.5) {
      relaxation = previous_relaxation_ / (1.0 - ratio);
    } else if (ratio > 0.5 && ratio < 1.0 && cosine > kAligned && steady && previous_relaxation_ == 1.0) {
      relaxation = std::min(1.0 / (1.0 - ratio), kMostExtrapolation);
    }
  }
  previous_step_ = step;
  previous_ratio_ = ratio;
  previous_relaxation_ = relaxation;
  return relaxation;
}

}  // namespace csim
