#include "engine/steppers/summary_entries.h"

namespace csim {

void add_newton_group(const SolverCounters& c, double tolerance, SummaryEntries& out) {
  out.begin_group("newton")
      .add("tolerance", tolerance)
      .add("iterations", c.newton_iterations)
      .add("mean_per_step", c.steps > 0 ? double(c.newton_iterations) / c.steps : 0.0)
      .add("max_per_step", c.max_newton_iterations)
      .add("regularized_iterations", c.newton_regularized)
      .add("contact_held_iterations", c.newton_held)
      .add("kept_factor_iterations", c.newton_kept_factor)
      .add("relaxed_iterations", c.newton_relaxed)
      .add("backtracks", c.newton_backtracks)
      .add("redetections", c.newton_redetections)
      .add("activated_contacts", c.newton_activated_contacts)
      .add("cutbacks", c.cutbacks)
      .end_group();
}

}  // namespace csim
