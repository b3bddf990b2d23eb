#include "contact/coulomb_local.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

// Everything here works on fixed-size Eigen objects: these solves run once per contact per PGS sweep,
// millions of times per run, and must never touch the heap.
//
// The 3D slip search and the fallback measure of how well a candidate satisfies the law both work in
// "scaled" coordinates that turn the orthotropic cone into the unit isotropic one:
//   r' = S⁻¹ r,  u' = S u,  S = diag(1, μ1, μ2),   so  u' = (S W S) r' + S q,  r'·u' = r·u,
// and the law becomes |r'_t| ≤ r'_n with r'_t = −r'_n u'_t/|u'_t| in slip (μ = 1). This is exact only
// when both μ_i > 0; a zero μ_i is handled before, by dropping that axis.

namespace csim {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double square(double x) { return x * x; }

// A normal row that (relative to the contact's other mobilities) cannot move, cannot be pushed apart
// either: the only answer the law leaves is r = 0. Written so that NaN also fails.
bool normal_is_mobile(double w_nn, double largest_diagonal) {
  return w_nn > std::numeric_limits<double>::min() && w_nn > 1e-14 * largest_diagonal;
}

// Euclidean projection onto the unit second-order cone {x : |x_t| ≤ x_n}.
template <int N>
Eigen::Matrix<double, N, 1> project_on_unit_cone(const Eigen::Matrix<double, N, 1>& x) {
  const double normal = x(0);
  const double tangential = x.template tail<N - 1>().norm();
  if (tangential <= normal) return x;
  if (tangential <= -normal) return Eigen::Matrix<double, N, 1>::Zero();
  const double radius = 0.5 * (normal + tangential);
  Eigen::Matrix<double, N, 1> projected;
  projected(0) = radius;
  projected.template tail<N - 1>() = (radius / tangential) * x.template tail<N - 1>();
  return projected;
}

// How far r is from solving the unit-μ law u = W r + q, in velocity units (m/s): the De Saxcé natural
// map ‖r − P_K(r − ρ(u + |u_t| e_n))‖/ρ with ρ = 1/W_nn. Zero exactly at a solution. Used only to
// choose among candidates when round-off makes every case fail its exact test.
template <int N>
double law_error_unit_cone(const Eigen::Matrix<double, N, N>& W, const Eigen::Matrix<double, N, 1>& q,
                           const Eigen::Matrix<double, N, 1>& r) {
  const double rho = 1.0 / W(0, 0);
  Eigen::Matrix<double, N, 1> u = W * r + q;
  u(0) += u.template tail<N - 1>().norm();
  const double error = (r - project_on_unit_cone<N>(r - rho * u)).norm() / rho;
  return std::isnan(error) ? std::numeric_limits<double>::infinity() : error;
}

// Candidate chooser for the fallback: keeps the impulse with the smallest law error.
template <int N>
struct BestCandidate {
  const Eigen::Matrix<double, N, N>& W_scaled;
  const Eigen::Matrix<double, N, 1>& q_scaled;
  const Eigen::Matrix<double, N, 1>& scale;  // diag(S): r' = r ./ scale
  Eigen::Matrix<double, N, 1> r = Eigen::Matrix<double, N, 1>::Zero();
  double error = std::numeric_limits<double>::infinity();

  void offer(const Eigen::Matrix<double, N, 1>& candidate) {
    if (!candidate.allFinite()) return;
    const Eigen::Matrix<double, N, 1> candidate_scaled = candidate.cwiseQuotient(scale);
    const double candidate_error = law_error_unit_cone<N>(W_scaled, q_scaled, candidate_scaled);
    if (candidate_error < error) {
      error = candidate_error;
      r = candidate;
    }
  }
};

// Status of a fallback result, decided on the impulse alone (the exact paths know their case).
ContactStatus status_of(double r_n, double tangential_over_radius) {
  if (!(r_n > 0)) return ContactStatus::open;
  return tangential_over_radius < 1.0 ? ContactStatus::stick : ContactStatus::slip;
}

// ---- 2D ------------------------------------------------------------------------------------------

// Slip with r_t = −s μ r_n, s = sign(u_t) = ±1, and u_n = 0:
//   W_nn r_n − s μ W_nt r_n + q_n = 0  ⇒  r_n = −q_n / (W_nn − s μ W_nt),
// admissible when that denominator is positive (r_n > 0) and s·u_t ≥ 0 (friction opposes sliding).
struct Slip2d {
  bool has_positive_normal = false;
  bool opposes_sliding = false;
  Eigen::Vector2d r = Eigen::Vector2d::Zero();
};

Slip2d slip_2d(const Eigen::Matrix2d& W, const Eigen::Vector2d& q, double mu, double s) {
  Slip2d slip;
  const double denominator = W(0, 0) - s * mu * W(0, 1);
  if (!(denominator > 0)) return slip;
  slip.has_positive_normal = true;
  const double r_n = -q(0) / denominator;
  const double r_t = -s * mu * r_n;
  const double u_t = W(1, 0) * r_n + W(1, 1) * r_t + q(1);
  slip.r = Eigen::Vector2d(r_n, r_t);
  slip.opposes_sliding = s * u_t >= 0;
  return slip;
}

}  // namespace

const char* to_string(ContactStatus status) {
  switch (status) {
    case ContactStatus::open: return "open";
    case ContactStatus::stick: return "stick";
    case ContactStatus::slip: return "slip";
  }
  return "unknown";
}

ContactStatus solve_local_2d(const Eigen::Matrix2d& W, const Eigen::Vector2d& q, double mu,
                             Eigen::Vector2d& r) {
  // Non-finite data give a non-finite answer, for the caller to reject, rather than a plausible one.
  if (!W.allFinite() || !q.allFinite() || std::isnan(mu)) {
    r.setConstant(kNaN);
    return ContactStatus::open;
  }
  if (!normal_is_mobile(W(0, 0), std::max(W(0, 0), W(1, 1))) || q(0) >= 0) {
    r.setZero();
    return ContactStatus::open;
  }
  // From here q_n < 0: r_n = 0 would leave u_n = q_n < 0, so the contact is closed and u_n = 0.
  const double r_n_frictionless = -q(0) / W(0, 0);
  if (!(mu > 0)) {
    // r_t = 0 is the whole (degenerate) disk, hence on its boundary: reported as slip.
    r = Eigen::Vector2d(r_n_frictionless, 0.0);
    return ContactStatus::slip;
  }

  // Stick: W r = −q.
  const double det = W(0, 0) * W(1, 1) - W(0, 1) * W(1, 0);
  const bool stick_computable = det > 1e-14 * W(0, 0) * W(1, 1);
  Eigen::Vector2d r_stick = Eigen::Vector2d::Zero();
  if (stick_computable) {
    r_stick = Eigen::Vector2d(W(0, 1) * q(1) - W(1, 1) * q(0), W(1, 0) * q(0) - W(0, 0) * q(1)) / det;
    if (r_stick(0) > 0 && std::abs(r_stick(1)) <= mu * r_stick(0)) {
      r = r_stick;
      return ContactStatus::stick;
    }
  }

  // Slip: try first the sliding direction the failed stick points to (friction would have had to
  // exceed the cone against it), then the other; in the well-posed case only one is admissible.
  double s_first = 1.0;
  if (stick_computable && r_stick(1) != 0.0) {
    s_first = r_stick(1) < 0 ? 1.0 : -1.0;
  } else {
    const double u_t_frictionless = q(1) + W(1, 0) * r_n_frictionless;
    s_first = u_t_frictionless >= 0 ? 1.0 : -1.0;
  }
  const Slip2d slip_first = slip_2d(W, q, mu, s_first);
  if (slip_first.has_positive_normal && slip_first.opposes_sliding) {
    r = slip_first.r;
    return ContactStatus::slip;
  }
  const Slip2d slip_second = slip_2d(W, q, mu, -s_first);
  if (slip_second.has_positive_normal && slip_second.opposes_sliding) {
    r = slip_second.r;
    return ContactStatus::slip;
  }

  // No case passed its exact test: round-off at the stick/slip threshold, a singular W, or a
  // Painlevé-like W_nt so large that no solution exists. Take the candidate closest to the law.
  const Eigen::Vector2d scale(1.0, mu);
  const Eigen::Matrix2d W_scaled = scale.asDiagonal() * W * scale.asDiagonal();
  const Eigen::Vector2d q_scaled = scale.cwiseProduct(q);
  BestCandidate<2> best{W_scaled, q_scaled, scale};
  best.offer(Eigen::Vector2d(r_n_frictionless, 0.0));
  if (stick_computable) {
    const double r_n = std::max(r_stick(0), 0.0);
    best.offer(Eigen::Vector2d(r_n, std::clamp(r_stick(1), -mu * r_n, mu * r_n)));
  }
  if (slip_first.has_positive_normal) best.offer(slip_first.r);
  if (slip_second.has_positive_normal) best.offer(slip_second.r);
  r = best.r;
  return status_of(r(0), std::abs(r(1)) / (mu * r(0)));
}

// ---- 3D ------------------------------------------------------------------------------------------

namespace {

// The slip equations in scaled (unit-μ) coordinates, as a function of the direction e = (cos φ, sin φ)
// of r'_t = r'_n e. With g = (1, cos φ, sin φ):
//   u_n = 0        ⇒  r'_n = −q_n / D,  D(φ) = W'_n·g   (needs D > 0)
//   D u'_t  = v(φ) = B g,  B = (−q_n) W'_t + q'_t W'_n   (D > 0 scales the velocity, keeps its direction)
//   slip    ⇔  e × v = 0 and e·v ≤ 0  (e opposite to the sliding velocity).
// Two functions of φ have these roots:
//   f(φ) = e × v, a trigonometric polynomial of degree 2 (at most four roots), continuous everywhere:
//          its sign changes bracket every root, admissible or not, which is what the scan needs;
//   h(φ) = signed angle from e to −v, in (−π, π]: zero only at the admissible roots (the others sit on
//          its ±π jump), which keeps the fast Newton path away from friction-aids-sliding solutions.
class SlipEquations {
 public:
  SlipEquations(const Eigen::Matrix3d& W_scaled, const Eigen::Vector3d& q_scaled)
      : pressure_(-q_scaled(0)), normal_row_(W_scaled.row(0)) {
    B_.noalias() = pressure_ * W_scaled.bottomRows<2>() + q_scaled.tail<2>() * normal_row_;
  }

  struct Point {
    double D = 0;      // W'_n·g, > 0 for an admissible root
    double f = 0;      // e × v
    double df = 0;     // df/dφ
    double along = 0;  // e·v, ≤ 0 for an admissible root
    Eigen::Vector2d v = Eigen::Vector2d::Zero();
    Eigen::Vector2d dv = Eigen::Vector2d::Zero();
  };

  Point at(const Eigen::Vector2d& e) const {
    const Eigen::Vector3d g(1.0, e(0), e(1));
    const Eigen::Vector3d dg(0.0, -e(1), e(0));
    Point point;
    point.D = normal_row_.dot(g);
    point.v.noalias() = B_ * g;
    point.dv.noalias() = B_ * dg;
    point.f = e(0) * point.v(1) - e(1) * point.v(0);
    point.along = e(0) * point.v(0) + e(1) * point.v(1);
    point.df = -point.along + e(0) * point.dv(1) - e(1) * point.dv(0);
    return point;
  }

  static bool admissible(const Point& point) { return point.D > 0 && point.along <= 0; }

  // r' = r'_n (1, e) at an admissible direction.
  Eigen::Vector3d scaled_impulse(const Eigen::Vector2d& e) const {
    const double r_n = pressure_ / normal_row_.dot(Eigen::Vector3d(1.0, e(0), e(1)));
    return Eigen::Vector3d(r_n, r_n * e(0), r_n * e(1));
  }

 private:
  double pressure_;                          // −q_n > 0 (m/s)
  Eigen::RowVector3d normal_row_;            // W'_n
  Eigen::Matrix<double, 2, 3> B_;
};

Eigen::Vector2d rotated(const Eigen::Vector2d& e, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return Eigen::Vector2d(c * e(0) - s * e(1), s * e(0) + c * e(1));
}

// True if x lies strictly inside the arc from a to b, an arc shorter than π.
bool inside_arc(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& x) {
  const auto cross = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q) { return p(0) * q(1) - p(1) * q(0); };
  const double orientation = cross(a, b);
  return cross(a, x) * orientation > 0 && cross(x, b) * orientation > 0 && x.dot(a + b) > 0;
}

// Fast path: Newton from e, at most 16 iterations. Returns true with e at an admissible root.
// Far from a root it steps on h (the angle to −v, which ignores the inadmissible roots); once e is
// within π/4 of −v it steps on f, whose nearest root is then the admissible one, to save
// the atan2. The direction is advanced as e ← normalise(e + δ e⊥), a rotation by atan δ: same root,
// same quadratic convergence, no trigonometric call; a step beyond about 70° (|δ| > 3), where the
// linear model is poor, turns by 45° that way instead.
// Newton on h alone can cycle where W_nt turns the sliding velocity strongly (Siconos' Rover problems:
// two directions 60° apart, each step jumping to the other; 8 iterations, the second guess's 8, then
// the scan). So the latest directions where f < 0 and f > 0 are kept: once they bracket a root of f
// within a quarter turn, Newton steps on f (no atan2), and a step that would leave the bracket is
// replaced by the bracket's bisection. The root so found is kept only if admissible; otherwise the
// caller's next guess and the scan follow, as before.
bool newton_slip(const SlipEquations& slip, Eigen::Vector2d& e) {
  constexpr int kMaxIterations = 16;
  Eigen::Vector2d negative = Eigen::Vector2d::Zero(), positive = Eigen::Vector2d::Zero();  // f < 0, f > 0
  bool has_negative = false, has_positive = false;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    const SlipEquations::Point point = slip.at(e);
    const bool near = point.along < 0 && std::abs(point.f) <= -point.along;  // |h| ≤ π/4
    // |sin h| = |f|/|v|: converged when the angle is at round-off level.
    if (near && std::abs(point.f) <= 4 * kEpsilon * point.v.norm()) return SlipEquations::admissible(point);
    if (point.f < 0) {
      negative = e;
      has_negative = true;
    } else if (point.f > 0) {
      positive = e;
      has_positive = true;
    }
    const bool bracketed = has_negative && has_positive && negative.dot(positive) > 0;
    double step = 0.0;
    if (near || bracketed) {
      step = -point.f / point.df;
    } else {
      const double h = std::atan2(-point.f, -point.along);
      // dh/dφ = d(angle of v)/dφ − 1
      const double dh =
          (point.v(0) * point.dv(1) - point.v(1) * point.dv(0)) / point.v.squaredNorm() - 1.0;
      step = -h / dh;
    }
    // A step beyond about 70° (tan 70° ≈ 3) means the linear model is poor: turn by 45° that way.
    if (!(std::abs(step) <= 3.0)) {
      if (std::isnan(step)) return false;
      step = step > 0 ? 1.0 : -1.0;
    }
    Eigen::Vector2d next = (e + step * Eigen::Vector2d(-e(1), e(0))).normalized();
    if (std::abs(step) <= 4 * kEpsilon) {
      e = next;
      return SlipEquations::admissible(slip.at(e));
    }
    if (bracketed && !inside_arc(negative, positive, next)) {
      // The bracket at round-off width: its ends are the root.
      if (std::abs(negative(0) * positive(1) - negative(1) * positive(0)) <= 4 * kEpsilon) {
        e = negative;
        return SlipEquations::admissible(slip.at(e));
      }
      next = (negative + positive).normalized();
    }
    e = next;
  }
  return false;
}

// True if e is an admissible root to round-off: Newton's first test, without its step.
bool is_slip_root(const SlipEquations& slip, const Eigen::Vector2d& e) {
  const SlipEquations::Point point = slip.at(e);
  return point.along < 0 && std::abs(point.f) <= 4 * kEpsilon * point.v.norm() && SlipEquations::admissible(point);
}

// Root of f in the arc [e_a, e_a rotated by width] (f changes sign over it), by Newton safeguarded with
// bisection, to machine precision in the angle.
Eigen::Vector2d refine_slip_root(const SlipEquations& slip, const Eigen::Vector2d& e_a, double f_a,
                                 double width) {
  double low = 0.0, high = width;
  const bool f_low_negative = f_a < 0;
  double theta = 0.5 * width;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const SlipEquations::Point point = slip.at(rotated(e_a, theta));
    if (point.f == 0.0) break;
    if ((point.f < 0) == f_low_negative) {
      low = theta;
    } else {
      high = theta;
    }
    double next = theta - point.f / point.df;
    if (!(next > low && next < high)) next = 0.5 * (low + high);
    const bool done = std::abs(next - theta) <= 2 * kEpsilon * std::max(1.0, std::abs(theta)) ||
                      high - low <= 4 * kEpsilon;
    theta = next;
    if (done) break;
  }
  return rotated(e_a, theta).normalized();
}

// Robust path: scan the circle from the guess for sign changes of f, refine each, and keep the
// admissible root nearest to the guess (the choice matters only where the law has several solutions;
// nearest keeps successive PGS sweeps on the same branch).
bool scan_slip(const SlipEquations& slip, const Eigen::Vector2d& guess, Eigen::Vector2d& e) {
  constexpr int kSamples = 64;
  constexpr double kStep = 2.0 * std::numbers::pi / kSamples;
  const double step_cos = std::cos(kStep), step_sin = std::sin(kStep);
  bool found = false;
  double best_distance = std::numeric_limits<double>::infinity();
  Eigen::Vector2d e_previous = guess;
  double f_previous = slip.at(e_previous).f;
  for (int k = 1; k <= kSamples; ++k) {
    // Rotation by recurrence: the sample directions need no precision, the refined roots are exact.
    const Eigen::Vector2d e_next =
        k == kSamples ? guess
                      : Eigen::Vector2d(step_cos * e_previous(0) - step_sin * e_previous(1),
                                        step_sin * e_previous(0) + step_cos * e_previous(1));
    const double f_next = slip.at(e_next).f;
    if (f_previous == 0.0 || (f_previous < 0) != (f_next < 0)) {
      const Eigen::Vector2d root =
          f_previous == 0.0 ? e_previous : refine_slip_root(slip, e_previous, f_previous, kStep);
      const double angle_from_guess = (k - 0.5) * kStep;
      const double distance = std::min(angle_from_guess, 2.0 * std::numbers::pi - angle_from_guess);
      if (SlipEquations::admissible(slip.at(root)) && distance < best_distance) {
        found = true;
        best_distance = distance;
        e = root;
      }
    }
    e_previous = e_next;
    f_previous = f_next;
  }
  return found;
}

// Elliptic "radius" of r_t relative to r_n: ((r_t1/μ1)² + (r_t2/μ2)²)^½ / r_n, for μ1, μ2 > 0.
double cone_ratio(const Eigen::Vector3d& r, const Eigen::Vector2d& mu) {
  return std::hypot(r(1) / mu(0), r(2) / mu(1)) / r(0);
}

}  // namespace

namespace {

// True if r' (scaled coordinates) slips by the unit-μ law to round-off: r'_n > 0, |r'_t| = r'_n,
// u'_n = 0 and u'_t opposite to r'_t, each within 16 ε of the scale of its terms (Newton's roots pass
// it with a margin: they stop at 4 ε in the angle).
bool slips_to_round_off(const Eigen::Matrix3d& W_scaled, const Eigen::Vector3d& q_scaled, const Eigen::Vector3d& r) {
  constexpr double kRoundOff = 16 * kEpsilon;
  if (!(r(0) > 0)) return false;
  const double tangential = r.tail<2>().norm();
  if (!(std::abs(tangential - r(0)) <= kRoundOff * r(0))) return false;
  const Eigen::Vector3d u = W_scaled * r + q_scaled;
  const Eigen::Vector3d u_scale = W_scaled.cwiseAbs() * r.cwiseAbs() + q_scaled.cwiseAbs();
  if (!(std::abs(u(0)) <= kRoundOff * u_scale(0))) return false;
  const double along = r(1) * u(1) + r(2) * u(2);
  const double across = r(1) * u(2) - r(2) * u(1);
  return along <= 0 && std::abs(across) <= kRoundOff * tangential * u_scale.tail<2>().norm();
}

ContactStatus solve_local_3d_from(const Eigen::Matrix3d& W, const Eigen::Vector3d& q, const Eigen::Vector2d& mu,
                                  Eigen::Vector3d& r, const Eigen::Vector3d* start, const StickInverse* given) {
  if (!W.allFinite() || !q.allFinite() || mu.hasNaN()) {
    r.setConstant(kNaN);
    return ContactStatus::open;
  }
  if (!normal_is_mobile(W(0, 0), W.diagonal().maxCoeff()) || q(0) >= 0) {
    r.setZero();
    return ContactStatus::open;
  }
  const double r_n_frictionless = -q(0) / W(0, 0);
  const bool rough1 = mu(0) > 0;
  const bool rough2 = mu(1) > 0;
  if (!rough1 && !rough2) {
    r = Eigen::Vector3d(r_n_frictionless, 0.0, 0.0);
    return ContactStatus::slip;
  }
  if (!rough1 || !rough2) {
    // Unidirectional friction: with r_tk = 0 forced on the smooth axis, its velocity is free and the law
    // on (n, t_rough) is exactly the 2D one.
    const int rough = rough1 ? 1 : 2;
    const int smooth = rough1 ? 2 : 1;
    Eigen::Matrix2d W2;
    W2 << W(0, 0), W(0, rough), W(rough, 0), W(rough, rough);
    Eigen::Vector2d r2;
    const ContactStatus status = solve_local_2d(W2, Eigen::Vector2d(q(0), q(rough)), mu(rough - 1), r2);
    r(0) = r2(0);
    r(rough) = r2(1);
    r(smooth) = 0.0;
    return status;
  }

  // Stick: W r = −q (stick_inverse, or the one given).
  StickInverse computed;
  if (given == nullptr) computed = stick_inverse(W);
  const StickInverse& stick = given != nullptr ? *given : computed;
  const Eigen::Matrix3d& W_inverse = stick.inverse;
  const bool stick_computable = stick.computable;
  Eigen::Vector3d r_stick = Eigen::Vector3d::Zero();
  if (stick_computable) {
    r_stick.noalias() = -W_inverse * q;
    if (r_stick(0) > 0 && square(r_stick(1) / mu(0)) + square(r_stick(2) / mu(1)) <= square(r_stick(0))) {
      r = r_stick;
      return ContactStatus::stick;
    }
  }

  // Slip, in scaled coordinates.
  const Eigen::Vector3d scale(1.0, mu(0), mu(1));
  const Eigen::Matrix3d W_scaled = scale.asDiagonal() * W * scale.asDiagonal();
  const Eigen::Vector3d q_scaled = scale.cwiseProduct(q);
  const SlipEquations slip(W_scaled, q_scaled);

  // First guess: opposite to the sliding velocity after a frictionless normal impulse. When W_nt = 0
  // and W'_tt ∝ I that velocity does not turn when friction is applied, so the guess is the root.
  Eigen::Vector2d guess = -(q_scaled.tail<2>() + W_scaled.block<2, 1>(1, 0) * r_n_frictionless);
  if (!(guess.norm() > 0) || !guess.allFinite()) {
    guess = stick_computable ? Eigen::Vector2d(r_stick(1) / mu(0), r_stick(2) / mu(1))
                             : Eigen::Vector2d(1.0, 0.0);
    if (!(guess.norm() > 0) || !guess.allFinite()) guess = Eigen::Vector2d(1.0, 0.0);
  }
  guess.normalize();

  // Second guess, when the first fails: the direction of the (rejected) stick impulse, good when
  // the coupling W_nt turns the sliding direction a lot.
  // The first guess when it is the root already (decoupled contacts: a point mass on a plane). Else a
  // start that already slips by the law to round-off is the answer as it is: so a Gauss–Seidel
  // contact whose impulse is its local solution keeps it to the bit, sweep after sweep, as it would
  // with a solve that ignores the start (the settled contacts of pgs_local.h rely on it). Otherwise
  // Newton from the start's slip direction (in a converging Gauss–Seidel, the previous sweep's: one or
  // two steps from the root), then from the first guess.
  Eigen::Vector2d e = guess;
  bool found = is_slip_root(slip, e);
  if (!found && start != nullptr) {
    if (slips_to_round_off(W_scaled, q_scaled, start->cwiseQuotient(scale))) {
      r = *start;
      return ContactStatus::slip;
    }
    if ((*start)(0) > 0) {
      e = Eigen::Vector2d((*start)(1) / mu(0), (*start)(2) / mu(1));
      const double norm = e.norm();
      if (norm > 0 && std::isfinite(norm)) {
        e /= norm;
        found = newton_slip(slip, e);
      }
      if (!found) e = guess;
    }
  }
  if (!found) found = newton_slip(slip, e);
  if (!found && stick_computable) {
    e = Eigen::Vector2d(r_stick(1) / mu(0), r_stick(2) / mu(1));
    if (e.norm() > 0) {
      e.normalize();
      found = newton_slip(slip, e);
    }
  }
  if (found || scan_slip(slip, guess, e)) {
    r = scale.cwiseProduct(slip.scaled_impulse(e));
    return ContactStatus::slip;
  }

  // Nothing passed its exact test (round-off at the threshold, singular W, or no solution at all):
  // take the candidate closest to the law.
  BestCandidate<3> best{W_scaled, q_scaled, scale};
  best.offer(Eigen::Vector3d(r_n_frictionless, 0.0, 0.0));
  if (stick_computable) {
    Eigen::Vector3d clamped = r_stick;
    clamped(0) = std::max(clamped(0), 0.0);
    const double ratio = cone_ratio(clamped, mu);
    if (!(ratio <= 1.0)) clamped.tail<2>() *= clamped(0) > 0 ? 1.0 / ratio : 0.0;
    best.offer(clamped);
  }
  for (const Eigen::Vector2d& direction : {e, guess}) {
    if (slip.at(direction).D > 0) best.offer(scale.cwiseProduct(slip.scaled_impulse(direction)));
  }
  r = best.r;
  return status_of(r(0), cone_ratio(r, mu));
}

}  // namespace

StickInverse stick_inverse(const Eigen::Matrix3d& W) {
  // Hadamard's bound det ≤ W_nn W_t1t1 W_t2t2 gives the scale of "singular".
  StickInverse stick;
  double det = 0.0;
  W.computeInverseAndDetWithCheck(stick.inverse, det, stick.computable, 1e-14 * std::abs(W(0, 0) * W(1, 1) * W(2, 2)));
  return stick;
}

ContactStatus solve_local_3d(const Eigen::Matrix3d& W, const StickInverse& stick, const Eigen::Vector3d& q,
                             const Eigen::Vector2d& mu, Eigen::Vector3d& r, const Eigen::Vector3d& start) {
  return solve_local_3d_from(W, q, mu, r, &start, &stick);
}

ContactStatus solve_local_3d(const Eigen::Matrix3d& W, const Eigen::Vector3d& q,
                             const Eigen::Vector2d& mu, Eigen::Vector3d& r) {
  return solve_local_3d_from(W, q, mu, r, nullptr, nullptr);
}

ContactStatus solve_local_3d(const Eigen::Matrix3d& W, const Eigen::Vector3d& q,
                             const Eigen::Vector2d& mu, Eigen::Vector3d& r, const Eigen::Vector3d& start) {
  return solve_local_3d_from(W, q, mu, r, &start, nullptr);
}

}  // namespace csim
