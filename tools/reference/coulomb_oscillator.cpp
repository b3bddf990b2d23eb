#include "tools/reference/coulomb_oscillator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

namespace csim {

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

// The direction of the motion, or of the motion about to start. Its sign is the s of the header.
enum class Motion { slip_up = 1, slip_down = -1, stick = 0 };

int sign_of(Motion motion) { return static_cast<int>(motion); }

// The loads seen by the mass, with the common ramp λ(t).
struct Loading {
  double stiffness;  // N/m
  double force;      // N, at λ = 1
  double friction;   // N, μN at λ = 1
  double ramp_time;  // s

  bool ramping(double t) const { return ramp_time > 0.0 && t < ramp_time; }
  double factor(double t) const { return ramping(t) ? t / ramp_time : 1.0; }
  // What friction has to hold for the mass to stay put: λF − kx (N).
  double unbalanced_force(double t, double x) const { return factor(t) * force - stiffness * x; }
  double friction_threshold(double t) const { return factor(t) * friction; }

  // At rest at (t, x), outside the time loop of a slip: stick, or the direction the slip starts in.
  Motion motion_from_rest(double t, double x) const {
    const double unbalanced = unbalanced_force(t, x);
    if (std::abs(unbalanced) <= friction_threshold(t)) return Motion::stick;
    return unbalanced > 0.0 ? Motion::slip_up : Motion::slip_down;
  }
};

std::string seconds(double t) {
  std::ostringstream out;
  out.precision(17);
  out << t << " s";
  return out.str();
}

struct Release {
  double time;    // s
  Motion motion;  // the slip that starts then
};

// When a stick at xs (m), begun at t (s), ends. During the ramp both sides of |λF − k xs| ≤ λμN are
// linear in t, so each of the two ways out, h_s(t) = λ(t)(sF − μN) − s·k·xs > 0, starts at the root of a
// linear function. After the ramp nothing changes any more: the stick is final.
std::optional<Release> stick_release(const Loading& loading, double t, double xs) {
  if (!loading.ramping(t)) {
    const Motion motion = loading.motion_from_rest(t, xs);
    if (motion == Motion::stick) return std::nullopt;
    return Release{t, motion};
  }
  std::optional<Release> earliest;
  for (const Motion motion : {Motion::slip_up, Motion::slip_down}) {
    const double s = sign_of(motion);
    const double load = s * loading.force - loading.friction;  // N, the ramped part of h_s at λ = 1
    const double h_now = loading.factor(t) * load - s * loading.stiffness * xs;
    double start = infinity;
    if (h_now > 0.0)
      start = t;  // only through rounding: the caller found the mass inside the friction cone
    else if (load > 0.0)
      start = std::max(t, loading.ramp_time * s * loading.stiffness * xs / load);
    // A root at the ramp end itself leaves the force exactly on the cone for ever after: no slip.
    if (start < loading.ramp_time && (!earliest || start < earliest->time)) earliest = Release{start, motion};
  }
  return earliest;
}

// The closed form of one phase, x(u) = c0 + c1·u + a·cos ωu + b·sin ωu, u = t − t0.
struct Harmonic {
  double c0, c1, a, b, omega;

  double position(double u) const { return c0 + c1 * u + a * std::cos(omega * u) + b * std::sin(omega * u); }
  double velocity(double u) const {
    return c1 + omega * (-a * std::sin(omega * u) + b * std::cos(omega * u));
  }
};

// The slip in direction s starting at (t0, x0, v0): the particular solution follows the load
// λ(t)(F − sμN), linear in t during the ramp, constant after it.
Harmonic slip_from(const Loading& loading, double omega, double t0, double x0, double v0, Motion motion) {
  const double net_load = loading.force - sign_of(motion) * loading.friction;  // N at λ = 1
  Harmonic h{};
  h.omega = omega;
  if (loading.ramping(t0)) {
    h.c1 = net_load / (loading.stiffness * loading.ramp_time);
    h.c0 = h.c1 * t0;
  } else {
    h.c0 = net_load / loading.stiffness;
  }
  h.a = x0 - h.c0;
  h.b = (v0 - h.c1) / omega;
  return h;
}

struct Stop {
  double u;  // s after the start of the phase
  double x;  // m
};

// Below this distance of p to 1 the velocity only touches zero (to rounding) instead of changing sign.
// It happens when a slip starts from a stick during the ramp: v ∝ 1 − cos ωu grows from zero and would
// touch zero again one period later, where rounding could fake a reversal of size ~1e-16.
constexpr double tangency_tolerance = 1e-13;

// The first instant u > 0 where the velocity of the slip in direction s changes sign, in closed form.
// With (a_s, b_s) = s(a, b), R = |(a, b)| and α_s = atan2(b_s, a_s), the velocity is
//   s·v(u) = s·c1 + ωR·sin(α_s − ωu),
// which goes from positive to negative where sin(α_s − ωu) = −p, p = s·c1/(ωR), with cos(α_s − ωu) > 0:
// ωu = α_s + asin p (mod 2π). There x − (c0 + c1·u) = s·R·√(1 − p²), without cancellation.
std::optional<Stop> velocity_reversal(const Harmonic& h, Motion motion) {
  const double s = sign_of(motion);
  const double amplitude = std::hypot(h.a, h.b);
  const double p = amplitude > 0.0 ? s * h.c1 / (h.omega * amplitude) : (s * h.c1 > 0.0 ? infinity : -infinity);
  if (p >= 1.0 - tangency_tolerance) return std::nullopt;  // s·v ≥ 0 throughout
  if (p <= -1.0) return Stop{0.0, h.c0 + h.a};             // not moving in direction s at all: stops now
  double phase = std::atan2(s * h.b, s * h.a) + std::asin(p);
  if (phase <= 0.0) phase += 2.0 * std::numbers::pi;
  const double u = phase / h.omega;
  return Stop{u, h.c0 + h.c1 * u + s * amplitude * std::sqrt((1.0 - p) * (1.0 + p))};
}

void check_model(const CoulombOscillator& m, double t_end) {
  const double values[] = {m.mass, m.stiffness, m.force, m.normal_force, m.mu, m.ramp_time, m.x0, m.v0, t_end};
  if (!std::all_of(std::begin(values), std::end(values), [](double v) { return std::isfinite(v); }))
    throw std::invalid_argument("CoulombOscillator: all parameters and t_end must be finite");
  if (m.mass <= 0.0 || m.stiffness <= 0.0)
    throw std::invalid_argument("CoulombOscillator: mass and stiffness must be positive");
  if (m.mu < 0.0 || m.normal_force < 0.0 || m.ramp_time < 0.0 || t_end < 0.0)
    throw std::invalid_argument("CoulombOscillator: mu, normal_force, ramp_time and t_end must be non-negative");
}

}  // namespace

CoulombOscillatorSolution::CoulombOscillatorSolution(const CoulombOscillator& model, double t_end)
    : t_end_(t_end) {
  check_model(model, t_end);
  omega_ = std::sqrt(model.stiffness / model.mass);
  build(model);
}

// Event-driven: each pass appends the closed form of one phase and moves (t, x, v) to its end, which is
// a velocity reversal, a stick release, or the end of the ramp (where the load stops growing).
constexpr std::size_t kMaximumPieces = 1000000;

void CoulombOscillatorSolution::build(const CoulombOscillator& model) {
  const Loading loading{model.stiffness, model.force, model.mu * model.normal_force, model.ramp_time};
  double t = 0.0, x = model.x0, v = model.v0;
  Motion motion = v > 0.0 ? Motion::slip_up : (v < 0.0 ? Motion::slip_down : loading.motion_from_rest(t, x));

  // Every phase but a degenerate one has a positive duration; this only guards against a bug looping.
  int passes_without_progress = 0;
  while (t <= t_end_) {
    // A bound on the phases kept: a scene with a period far below its time window (say 1e-150 s)
    // would otherwise fill the memory with half-cycles.
    if (pieces_.size() >= kMaximumPieces) {
      std::ostringstream message;
      message << "CoulombOscillator: more than " << kMaximumPieces << " motion phases in the time window "
              << "(period " << 2.0 * M_PI / omega_ << " s); shorten the window";
      throw std::invalid_argument(message.str());
    }
    const double t_start = t;
    if (motion == Motion::stick) {
      const std::optional<Release> release = stick_release(loading, t, x);
      if (!release || release->time > t) pieces_.push_back({t, x, 0.0, 0.0, 0.0});
      if (!release) {
        at_rest_ = true;
        rest_time_ = t;  // the last stop, or 0 if the mass never moved
        rest_position_ = x;
        return;
      }
      t = release->time;
      v = 0.0;
      motion = release->motion;
    } else {
      const Harmonic slip = slip_from(loading, omega_, t, x, v, motion);
      pieces_.push_back({t, slip.c0, slip.c1, slip.a, slip.b});
      const double phase_end = loading.ramping(t) ? loading.ramp_time : infinity;
      const std::optional<Stop> stop = velocity_reversal(slip, motion);
      if (stop && t + stop->u <= phase_end) {
        t += stop->u;
        if (t > t_end_) return;
        x = stop->x;
        v = 0.0;
        if (t > 0.0) extrema_.push_back({t, x});
        motion = loading.motion_from_rest(t, x);
      } else if (phase_end < infinity) {
        const double u = phase_end - t;
        t = phase_end;
        x = slip.position(u);
        v = slip.velocity(u);
        // The reversal and the ramp end coincide to rounding: a stop, decided with the full load.
        if (sign_of(motion) * v <= 0.0) {
          v = 0.0;
          if (t <= t_end_) extrema_.push_back({t, x});
          motion = loading.motion_from_rest(t, x);
        }
      } else {
        return;  // slides on beyond t_end (only a sliding start without reversal can get here)
      }
    }
    passes_without_progress = t > t_start ? 0 : passes_without_progress + 1;
    if (passes_without_progress > 8)
      throw std::logic_error("CoulombOscillatorSolution: no progress at t = " + seconds(t));
  }
}

const CoulombOscillatorSolution::Piece& CoulombOscillatorSolution::piece_at(double t, const char* what) const {
  if (!(t >= 0.0 && t <= t_end_))
    throw std::out_of_range(std::string("CoulombOscillatorSolution::") + what + ": t = " + seconds(t) +
                            " is outside [0, " + seconds(t_end_) + "]");
  const auto after = std::upper_bound(pieces_.begin(), pieces_.end(), t,
                                      [](double time, const Piece& piece) { return time < piece.t0; });
  return *std::prev(after);
}

double CoulombOscillatorSolution::position(double t) const {
  const Piece& p = piece_at(t, "position");
  return Harmonic{p.c0, p.c1, p.a, p.b, omega_}.position(t - p.t0);
}

double CoulombOscillatorSolution::velocity(double t) const {
  const Piece& p = piece_at(t, "velocity");
  return Harmonic{p.c0, p.c1, p.a, p.b, omega_}.velocity(t - p.t0);
}

int CoulombOscillatorSolution::extremum_count() const { return static_cast<int>(extrema_.size()); }

const CoulombOscillatorSolution::Extremum& CoulombOscillatorSolution::extremum(int index) const {
  if (index < 1 || index > extremum_count())
    throw std::out_of_range("CoulombOscillatorSolution: extremum index " + std::to_string(index) +
                            " out of range; there are " + std::to_string(extremum_count()) +
                            " extrema (indices from 1) in [0, " + seconds(t_end_) + "]");
  return extrema_[static_cast<std::size_t>(index - 1)];
}

double CoulombOscillatorSolution::extremum_time(int index) const { return extremum(index).time; }

double CoulombOscillatorSolution::extremum_value(int index) const { return extremum(index).value; }

bool CoulombOscillatorSolution::comes_to_rest() const { return at_rest_; }

double CoulombOscillatorSolution::rest_time() const {
  if (!at_rest_)
    throw std::logic_error("CoulombOscillatorSolution: the mass is still moving at t_end = " + seconds(t_end_));
  return rest_time_;
}

double CoulombOscillatorSolution::rest_position() const {
  if (!at_rest_)
    throw std::logic_error("CoulombOscillatorSolution: the mass is still moving at t_end = " + seconds(t_end_));
  return rest_position_;
}

}  // namespace csim
