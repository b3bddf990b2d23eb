#include "contact/feature_clipping.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace csim {

namespace {

// Points closer than this (relative to the features' size) are one point: a stack of equal boxes puts
// incident vertices on the reference corners. Also the slack of every inside test and of the ties of
// the reduction.
constexpr double kRelativeTolerance = 1e-9;

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Area of the convex hull of four points in the plane (the largest of the three quadrilaterals).
double quad_area(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                 const Eigen::Vector2d& d) {
  auto shoelace = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r,
                     const Eigen::Vector2d& s) {
    return 0.5 * std::abs(cross2(p, q) + cross2(q, r) + cross2(r, s) + cross2(s, p));
  };
  return std::max({shoelace(a, b, c, d), shoelace(a, b, d, c), shoelace(a, c, b, d)});
}

// The index of the largest score, the first of those within `slack` of it.
template <typename Score>
std::size_t first_best(const std::vector<ClippedPoint>& points, Score&& score, double slack) {
  double best = score(points[0]);
  for (std::size_t i = 1; i < points.size(); ++i) best = std::max(best, score(points[i]));
  for (std::size_t i = 0; i < points.size(); ++i)
    if (score(points[i]) >= best - slack) return i;
  return 0;
}

void reduce(std::vector<ClippedPoint>& points, double tolerance, std::vector<ClippedPoint>& kept) {
  if (points.size() <= kMaxManifoldPoints) return;
  const double size = std::max(tolerance / kRelativeTolerance, 1e-300);
  const double area_slack = kRelativeTolerance * size * size;
  const std::size_t p0 = first_best(points, [](const ClippedPoint& c) { return -c.gap; }, tolerance);
  const Eigen::Vector2d a = points[p0].in_plane;
  const std::size_t p1 = first_best(points, [&](const ClippedPoint& c) { return (c.in_plane - a).squaredNorm(); }, area_slack);
  const Eigen::Vector2d b = points[p1].in_plane;
  const std::size_t p2 =
      first_best(points, [&](const ClippedPoint& c) { return std::abs(cross2(b - a, c.in_plane - a)); }, area_slack);
  const Eigen::Vector2d d = points[p2].in_plane;
  const std::size_t p3 = first_best(points, [&](const ClippedPoint& c) { return quad_area(a, b, d, c.in_plane); }, area_slack);
  kept.clear();
  for (std::size_t i : {p0, p1, p2, p3}) kept.push_back(points[i]);
  points.swap(kept);
}

class Clipper {
 public:
  Clipper(const SupportFeature& reference, const Eigen::Vector3d& normal, const SupportFeature& incident,
          int id_bound, ClipScratch& scratch)
      : reference_(reference), incident_(incident), normal_(normal), id_bound_(id_bound),
        reference_2d_(scratch.reference_2d), incident_2d_(scratch.incident_2d), heights_(scratch.heights) {
    reference_2d_.clear(), incident_2d_.clear(), heights_.clear();
    centre_.setZero();
    for (const Eigen::Vector3d& p : reference.points) centre_ += p;
    centre_ /= reference.count();
    const Eigen::Vector3d first_edge = reference.points[1] - reference.points[0];
    u_ = (first_edge - first_edge.dot(normal) * normal).normalized();
    v_ = normal.cross(u_);
    double size = 0.0;
    for (const SupportFeature* feature : {&reference, &incident})
      for (const Eigen::Vector3d& p : feature->points) size = std::max(size, (p - centre_).norm());
    tolerance_ = kRelativeTolerance * size;
    for (const Eigen::Vector3d& p : reference.points) reference_2d_.push_back(in_plane(p));
    for (const Eigen::Vector3d& p : incident.points) {
      incident_2d_.push_back(in_plane(p));
      heights_.push_back(normal.dot(p - centre_));
    }
    reference_orientation_ = orientation(reference_2d_);
    incident_orientation_ = orientation(incident_2d_);
  }

  double tolerance() const { return tolerance_; }

  void clip(double margin, std::vector<ClippedPoint>& kept) const {
    kept.clear();
    auto offer = [&](const ClippedPoint& c) {
      if (c.gap > margin) return;
      for (const ClippedPoint& k : kept)
        if ((k.in_plane - c.in_plane).norm() <= tolerance_) return;
      kept.push_back(c);
    };
    const int m = incident_.count();
    const int n = reference_.count();
    for (int k = 0; k < m; ++k)
      if (over_reference(incident_2d_[k])) offer(incident_point(k));
    for (int j = 0; j < n; ++j) {
      ClippedPoint c;
      if (under_incident(j, c)) offer(c);
    }
    if (n >= 3) {  // a reference segment's side planes meet an incident segment at its reference points
      for (int k = 0; k < (m == 2 ? 1 : m); ++k)
        for (int j = 0; j < n; ++j) {
          ClippedPoint c;
          if (crossing(k, j, c)) offer(c);
        }
    }
  }

 private:
  // A reference segment constrains only the coordinate along it: across it (and along `normal`) the
  // incident points lie where the shapes' round-off and FCL's normal put them.
  Eigen::Vector2d in_plane(const Eigen::Vector3d& p) const {
    return {u_.dot(p - centre_), reference_.count() == 2 ? 0.0 : v_.dot(p - centre_)};
  }

  static double orientation(const std::vector<Eigen::Vector2d>& polygon) {
    if (polygon.size() < 3) return 0.0;
    double twice_area = 0.0;
    for (std::size_t k = 0; k < polygon.size(); ++k) twice_area += cross2(polygon[k], polygon[(k + 1) % polygon.size()]);
    return twice_area > 0.0 ? 1.0 : -1.0;
  }

  // Inside a convex polygon (within the tolerance), or between a segment's ends along it.
  bool inside(const std::vector<Eigen::Vector2d>& polygon, double orientation, const Eigen::Vector2d& q) const {
    if (polygon.size() == 2) {
      const Eigen::Vector2d d = polygon[1] - polygon[0];
      const double length = d.norm();
      const double t = d.dot(q - polygon[0]) / length;
      return t >= -tolerance_ && t <= length + tolerance_;
    }
    for (std::size_t k = 0; k < polygon.size(); ++k) {
      const Eigen::Vector2d edge = polygon[(k + 1) % polygon.size()] - polygon[k];
      if (orientation * cross2(edge, q - polygon[k]) < -tolerance_ * edge.norm()) return false;
    }
    return true;
  }

  bool over_reference(const Eigen::Vector2d& q) const { return inside(reference_2d_, reference_orientation_, q); }

  ClippedPoint incident_point(int k) const {
    ClippedPoint c;
    c.in_plane = incident_2d_[k];
    c.gap = heights_[k];
    c.incident_point = incident_.points[k];
    c.reference_point = incident_.points[k] - c.gap * normal_;
    c.incident_arm = incident_.arms[k];
    c.reference_arm = Eigen::Vector3d::Constant(std::nan(""));
    c.feature = incident_.ids[k];
    return c;
  }

  // Reference point j where it lies under the incident feature: an incident polygon (over a reference
  // polygon or segment), or an incident segment over a reference segment (its side planes' crossings).
  bool under_incident(int j, ClippedPoint& out) const {
    const int m = incident_.count();
    const Eigen::Vector3d& corner = reference_.points[j];
    const Eigen::Vector2d q = reference_2d_[j];
    double gap = 0.0;
    if (m >= 3) {
      if (!inside(incident_2d_, incident_orientation_, q)) return false;
      // Newell's normal of the incident polygon; the corner moves along `normal` onto its plane.
      Eigen::Vector3d plane_normal = Eigen::Vector3d::Zero();
      for (int k = 0; k < m; ++k) plane_normal += incident_.points[k].cross(incident_.points[(k + 1) % m]);
      const double across = plane_normal.dot(normal_);
      if (across == 0.0) return false;
      gap = plane_normal.dot(incident_.points[0] - corner) / across;
    } else if (m == 2 && reference_.count() == 2) {
      const Eigen::Vector2d d = incident_2d_[1] - incident_2d_[0];
      const double length = d.norm();
      if (length <= tolerance_) return false;
      const double t = d.dot(q - incident_2d_[0]) / (length * length);
      if (t * length < -tolerance_ || (1.0 - t) * length < -tolerance_) return false;
      gap = heights_[0] + t * (heights_[1] - heights_[0]) - normal_.dot(corner - centre_);
    } else {
      return false;
    }
    out.in_plane = q;
    out.gap = gap;
    out.reference_point = corner;
    out.incident_point = corner + gap * normal_;
    out.reference_arm = reference_.arms[j];
    out.incident_arm = Eigen::Vector3d::Constant(std::nan(""));
    out.feature = id_bound_ + reference_.ids[j];
    return true;
  }

  // Incident edge k → k+1 crossing the side plane of reference edge j → j+1, within that edge.
  bool crossing(int k, int j, ClippedPoint& out) const {
    const int m = incident_.count();
    const int n = reference_.count();
    const Eigen::Vector2d& a = incident_2d_[k];
    const Eigen::Vector2d& b = incident_2d_[(k + 1) % m];
    const Eigen::Vector2d& r = reference_2d_[j];
    const Eigen::Vector2d& s = reference_2d_[(j + 1) % n];
    const Eigen::Vector2d ab = b - a, rs = s - r;
    const double denominator = cross2(ab, rs);
    const double ab_length = ab.norm(), rs_length = rs.norm();
    // Parallel to the side: its ends (incident or reference points) are the candidates.
    if (std::abs(denominator) <= tolerance_ * std::max(ab_length, rs_length)) return false;
    const double t = cross2(r - a, rs) / denominator;  // along the incident edge
    const double w = cross2(r - a, ab) / denominator;  // along the reference edge
    if (t * ab_length < -tolerance_ || (1.0 - t) * ab_length < -tolerance_) return false;
    if (w * rs_length < -tolerance_ || (1.0 - w) * rs_length < -tolerance_) return false;
    const int next = (k + 1) % m;
    out.in_plane = a + t * ab;
    out.gap = heights_[k] + t * (heights_[next] - heights_[k]);
    out.incident_point = incident_.points[k] + t * (incident_.points[next] - incident_.points[k]);
    out.reference_point = out.incident_point - out.gap * normal_;
    out.incident_arm = out.reference_arm = Eigen::Vector3d::Constant(std::nan(""));
    out.feature = 2 * id_bound_ + id_bound_ * incident_.ids[k] + reference_.ids[j];
    return true;
  }

  const SupportFeature& reference_;
  const SupportFeature& incident_;
  Eigen::Vector3d normal_;
  int id_bound_;
  Eigen::Vector3d centre_, u_, v_;
  double tolerance_ = 0.0;
  std::vector<Eigen::Vector2d>& reference_2d_;
  std::vector<Eigen::Vector2d>& incident_2d_;
  std::vector<double>& heights_;
  double reference_orientation_ = 0.0, incident_orientation_ = 0.0;
};

}  // namespace

void clip_features(const SupportFeature& reference, const Eigen::Vector3d& normal, const SupportFeature& incident,
                   double margin, int id_bound, ClipScratch& scratch, std::vector<ClippedPoint>& points) {
  points.clear();
  if (reference.count() < 2 || incident.count() < 2) return;
  const Clipper clipper(reference, normal, incident, id_bound, scratch);
  clipper.clip(margin, points);
  reduce(points, clipper.tolerance(), scratch.kept);
}

}  // namespace csim
