// The budget of one polish of PgsSolver (pgs_solver.h), in flops, and its one check, shared by every
// polish that spends it: the dense active set (active_set_polish.cpp), dense Newton (alart_curnier.h),
// sparse Newton (sparse_alart_curnier.h) and the sparse active set (sparse_active_set.h, sparse_pgs.cpp).
//
// A polish asks before work that it may not finish (a factorization, a line-search trial, a residual)
// whether `flops` more, and the reserve it must keep after them, fit in what is still available; when
// they do not, the budget is marked exhausted and the polish stops there. What each polish counts is
// stated in its own header.
#pragma once

#include <limits>

namespace csim {

struct PolishBudget {
  double available = std::numeric_limits<double>::infinity();  // flops the polish may still spend
  double spent = 0.0;                                           // flops spent so far
  int factorizations = 0;                                       // LU factorizations done
  int regularized_steps = 0;                                    // steps taken by a regularized system
  bool exhausted = false;                                       // work was refused

  // True if spent + flops… (added in the order given) is at most `available`; otherwise false, and
  // the budget exhausted. Counts nothing.
  template <typename... Flops>
  bool allows(Flops... flops) {
    if ((spent + ... + flops) <= available) return true;
    exhausted = true;
    return false;
  }

  // allows(flops, reserve), and then `flops` counted as spent.
  bool afford(double flops, double reserve = 0.0) {
    if (!allows(flops, reserve)) return false;
    spent += flops;
    return true;
  }
};

}  // namespace csim
