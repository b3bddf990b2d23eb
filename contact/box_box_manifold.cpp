#include "contact/box_box_manifold.h"

#include "contact/narrow_phase.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace csim {

namespace {

// A face normal within this of the contact normal (1 − |cos|, about 1.4e-3 rad) names the reference
// face. FCL's SAT returns a face normal exactly; GJK's witness direction (boxes apart by more than
// 1e-6 m) is close to it but not exact.
constexpr double kFaceAlignment = 1e-6;
// Points of the clipped polygon closer than this (relative to the larger box's largest half extent)
// are one point: a stack of equal boxes puts incident vertices on the reference face's corners.
constexpr double kRelativeTolerance = 1e-9;
constexpr int kMaxPoints = 4;

struct Posed {
  const Box& box;
  const Eigen::Isometry3d& pose;
};

// A face: outward normal sign · R.col(axis).
struct Face {
  int axis = 0;
  int sign = 1;
  double cosine = -1.0;  // |normal · direction| it was chosen for
};

// The face of `box` whose outward normal is best aligned with `direction` (first on ties).
Face best_face(const Posed& box, const Eigen::Vector3d& direction, bool planar) {
  Face best;
  for (int k = 0; k < (planar ? 2 : 3); ++k) {
    const double c = box.pose.linear().col(k).dot(direction);
    if (std::abs(c) > best.cosine) best = {k, c > 0.0 ? 1 : -1, std::abs(c)};
  }
  return best;
}

double face_size(const Box& box, const Face& face, bool planar) {
  const Eigen::Vector3d& h = box.half_extents;
  if (planar) return h[1 - face.axis];
  return h[(face.axis + 1) % 3] * h[(face.axis + 2) % 3];
}

// The box_vertex index of the corner with the given signs along the box axes.
int vertex_index(const std::array<int, 3>& signs) {
  return (signs[0] > 0 ? 1 : 0) | (signs[1] > 0 ? 2 : 0) | (signs[2] > 0 ? 4 : 0);
}

// A face's corners in cyclic order, as box_vertex indices (2 in plane scenes).
int face_corners(const Face& face, bool planar, std::array<int, 4>& corners) {
  std::array<int, 3> signs{};
  signs[face.axis] = face.sign;
  if (planar) {
    const int u = 1 - face.axis;
    for (int c = 0; c < 2; ++c) {
      signs[u] = c == 0 ? -1 : 1;
      corners[c] = vertex_index(signs);
    }
    return 2;
  }
  const int i = (face.axis + 1) % 3;
  const int j = (face.axis + 2) % 3;
  constexpr int kCycle[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int c = 0; c < 4; ++c) {
    signs[i] = kCycle[c][0];
    signs[j] = kCycle[c][1];
    corners[c] = vertex_index(signs);
  }
  return 4;
}

// A vertex of the clipped polygon.
struct Candidate {
  Eigen::Vector2d in_face;  // coordinates along the reference face's axes (m)
  Eigen::Vector3d incident_point;
  Eigen::Vector3d reference_point;
  double gap = 0.0;
  int feature = 0;
  Eigen::Vector3d incident_arm = Eigen::Vector3d::Constant(std::nan(""));
  Eigen::Vector3d reference_arm = Eigen::Vector3d::Constant(std::nan(""));
};

// The reference face in world coordinates: centre, outward normal, in-face axes and half sizes.
struct ReferenceFrame {
  Eigen::Vector3d centre;
  Eigen::Vector3d normal;
  Eigen::Vector3d u, v;
  double hu = 0.0, hv = 0.0;  // hv = 0 in plane scenes (a face is an edge)

  Eigen::Vector2d in_face(const Eigen::Vector3d& p) const { return {u.dot(p - centre), v.dot(p - centre)}; }
  double height(const Eigen::Vector3d& p) const { return normal.dot(p - centre); }
};

ReferenceFrame reference_frame(const Posed& box, const Face& face, bool planar) {
  const Eigen::Matrix3d& R = box.pose.linear();
  const Eigen::Vector3d& h = box.box.half_extents;
  ReferenceFrame f;
  f.normal = face.sign * R.col(face.axis);
  f.centre = box.pose.translation() + h[face.axis] * f.normal;
  const int i = planar ? 1 - face.axis : (face.axis + 1) % 3;
  f.u = R.col(i);
  f.hu = h[i];
  if (planar) {
    f.v = Eigen::Vector3d::UnitZ();
  } else {
    const int j = (face.axis + 2) % 3;
    f.v = R.col(j);
    f.hv = h[j];
  }
  return f;
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Keeps `c` unless an earlier candidate lies within `tolerance` of it in the face plane.
void keep_unless_duplicate(const Candidate& c, double tolerance, std::vector<Candidate>& kept) {
  for (const Candidate& k : kept) {
    if ((k.in_face - c.in_face).norm() <= tolerance) return;
  }
  kept.push_back(c);
}

// Area of the convex hull of four points in the plane (the largest of the three quadrilaterals).
double quad_area(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                 const Eigen::Vector2d& d) {
  auto shoelace = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r,
                     const Eigen::Vector2d& s) {
    return 0.5 * std::abs(cross2(p, q) + cross2(q, r) + cross2(r, s) + cross2(s, p));
  };
  return std::max({shoelace(a, b, c, d), shoelace(a, b, d, c), shoelace(a, c, b, d)});
}

// Reduces to kMaxPoints: the deepest, the farthest from it, then the points spanning the largest
// triangle and quadrilateral (Bullet's btPersistentManifold keeps the same four for the same reason:
// the support polygon is what keeps a box from tipping).
void reduce(std::vector<Candidate>& points) {
  if (points.size() <= kMaxPoints) return;
  auto arg_max = [&](auto&& score) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < points.size(); ++i) {
      if (score(points[i]) > score(points[best])) best = i;
    }
    return best;
  };
  const std::size_t p0 = arg_max([](const Candidate& c) { return -c.gap; });
  const Eigen::Vector2d a = points[p0].in_face;
  const std::size_t p1 = arg_max([&](const Candidate& c) { return (c.in_face - a).squaredNorm(); });
  const Eigen::Vector2d b = points[p1].in_face;
  const std::size_t p2 = arg_max([&](const Candidate& c) { return std::abs(cross2(b - a, c.in_face - a)); });
  const Eigen::Vector2d d = points[p2].in_face;
  const std::size_t p3 = arg_max([&](const Candidate& c) { return quad_area(a, b, d, c.in_face); });
  std::vector<Candidate> kept;
  for (std::size_t i : {p0, p1, p2, p3}) kept.push_back(points[i]);
  points = std::move(kept);
}

class Clipper {
 public:
  Clipper(const Posed& reference, const Face& reference_face, const Posed& incident, bool planar)
      : reference_(reference), incident_(incident), planar_(planar),
        frame_(reference_frame(reference, reference_face, planar)),
        incident_face_(best_face(incident, -frame_.normal, planar)) {
    const double size = std::max(reference.box.half_extents.maxCoeff(), incident.box.half_extents.maxCoeff());
    tolerance_ = kRelativeTolerance * size;
    corner_count_ = face_corners(incident_face_, planar, incident_corners_);
    for (int k = 0; k < corner_count_; ++k) {
      arms_[k] = incident.pose.linear() * box_vertex(incident.box, incident_corners_[k], planar);
      points_[k] = arms_[k] + incident.pose.translation();  // pose * vertex, to the bit
      in_face_[k] = frame_.in_face(points_[k]);
      heights_[k] = frame_.height(points_[k]);
    }
    reference_corner_count_ = face_corners(reference_face, planar, reference_corners_);
  }

  const ReferenceFrame& frame() const { return frame_; }

  // The clipped polygon's vertices with gap ≤ margin, without duplicates (an incident vertex first,
  // then a reference corner, then an edge crossing: the first named keeps a shared point).
  std::vector<Candidate> clip(double margin) const {
    std::vector<Candidate> kept;
    auto offer = [&](const Candidate& c) {
      if (c.gap <= margin) keep_unless_duplicate(c, tolerance_, kept);
    };
    for (int k = 0; k < corner_count_; ++k) {
      if (inside_reference(in_face_[k])) offer(incident_vertex(k));
    }
    for (int c = 0; c < reference_corner_count_; ++c) {
      Candidate candidate;
      if (reference_corner(c, candidate)) offer(candidate);
    }
    if (!planar_) {
      for (int k = 0; k < corner_count_; ++k) {
        for (int side = 0; side < 4; ++side) {
          Candidate candidate;
          if (edge_crossing(k, side, candidate)) offer(candidate);
        }
      }
    }
    return kept;
  }

 private:
  bool inside_reference(const Eigen::Vector2d& p) const {
    return std::abs(p.x()) <= frame_.hu + tolerance_ && std::abs(p.y()) <= frame_.hv + tolerance_;
  }

  Candidate incident_vertex(int k) const {
    Candidate c;
    c.in_face = in_face_[k];
    c.gap = heights_[k];
    c.incident_point = points_[k];
    c.reference_point = points_[k] - c.gap * frame_.normal;
    c.incident_arm = arms_[k];
    c.feature = incident_corners_[k];
    return c;
  }

  // Reference corner c where it lies on the incident face (inside its polygon, or on its segment in
  // plane scenes): the incident point is the corner moved along the reference normal onto the
  // incident face's plane.
  bool reference_corner(int c, Candidate& out) const {
    const Eigen::Vector3d arm =
        reference_.pose.linear() * box_vertex(reference_.box, reference_corners_[c], planar_);
    const Eigen::Vector3d corner = arm + reference_.pose.translation();
    const Eigen::Vector2d q = frame_.in_face(corner);
    double gap = 0.0;
    if (planar_) {
      const double dx = in_face_[1].x() - in_face_[0].x();
      const double t = (q.x() - in_face_[0].x()) / dx;  // |dx| ≥ the face's size / √2: well defined
      if (t * std::abs(dx) < -tolerance_ || (1.0 - t) * std::abs(dx) < -tolerance_) return false;
      gap = heights_[0] + t * (heights_[1] - heights_[0]);
    } else {
      const double orientation = cross2(in_face_[1] - in_face_[0], in_face_[2] - in_face_[0]) > 0.0 ? 1.0 : -1.0;
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector2d edge = in_face_[(k + 1) % 4] - in_face_[k];
        if (orientation * cross2(edge, q - in_face_[k]) < -tolerance_ * edge.norm()) return false;
      }
      const Eigen::Vector3d incident_normal =
          incident_face_.sign * incident_.pose.linear().col(incident_face_.axis);
      const Eigen::Vector3d incident_centre =
          incident_.pose.translation() + incident_.box.half_extents[incident_face_.axis] * incident_normal;
      gap = incident_normal.dot(incident_centre - corner) / incident_normal.dot(frame_.normal);
    }
    out.in_face = q;
    out.gap = gap;
    out.reference_point = corner;
    out.incident_point = corner + gap * frame_.normal;
    out.reference_arm = arm;
    out.feature = 8 + reference_corners_[c];
    return true;
  }

  // Incident edge k → k+1 crossing side `side` of the reference face (x = −hu, +hu, y = −hv, +hv).
  bool edge_crossing(int k, int side, Candidate& out) const {
    const int along = side / 2;  // 0: a side x = const, 1: y = const
    const double bound = (side % 2 == 0 ? -1.0 : 1.0) * (along == 0 ? frame_.hu : frame_.hv);
    const double half_width = along == 0 ? frame_.hv : frame_.hu;
    const Eigen::Vector2d& a = in_face_[k];
    const Eigen::Vector2d& b = in_face_[(k + 1) % 4];
    const double d = b[along] - a[along];
    const double length = (b - a).norm();
    if (std::abs(d) <= tolerance_) return false;  // parallel to the side: its ends are the candidates
    const double t = (bound - a[along]) / d;
    if (t * length < -tolerance_ || (1.0 - t) * length < -tolerance_) return false;
    const double across = a[1 - along] + t * (b[1 - along] - a[1 - along]);
    if (std::abs(across) > half_width + tolerance_) return false;
    out.in_face = a + t * (b - a);
    out.gap = heights_[k] + t * (heights_[(k + 1) % 4] - heights_[k]);
    out.incident_point = points_[k] + t * (points_[(k + 1) % 4] - points_[k]);
    out.reference_point = out.incident_point - out.gap * frame_.normal;
    const int face_id = 2 * incident_face_.axis + (incident_face_.sign > 0 ? 1 : 0);
    out.feature = 16 + 16 * face_id + 4 * k + side;
    return true;
  }

  const Posed& reference_;
  const Posed& incident_;
  bool planar_;
  ReferenceFrame frame_;
  Face incident_face_;
  double tolerance_ = 0.0;
  int corner_count_ = 0;
  std::array<int, 4> incident_corners_{};
  std::array<Eigen::Vector3d, 4> arms_, points_;
  std::array<Eigen::Vector2d, 4> in_face_;
  std::array<double, 4> heights_{};
  int reference_corner_count_ = 0;
  std::array<int, 4> reference_corners_{};
};

}  // namespace

int box_box_face_manifold(const Box& first, const Eigen::Isometry3d& first_pose, const Box& second,
                          const Eigen::Isometry3d& second_pose, const Eigen::Vector3d& normal,
                          double margin, bool planar, std::vector<ContactPoint>& out) {
  const Posed a{first, first_pose};
  const Posed b{second, second_pose};
  const Face on_first = best_face(a, normal, planar);
  const Face on_second = best_face(b, -normal, planar);
  const bool first_aligned = 1.0 - on_first.cosine <= kFaceAlignment;
  const bool second_aligned = 1.0 - on_second.cosine <= kFaceAlignment;
  if (!first_aligned && !second_aligned) return 0;  // edge–edge
  const bool reference_is_first =
      first_aligned &&
      (!second_aligned || face_size(first, on_first, planar) >= face_size(second, on_second, planar));

  const Clipper clipper = reference_is_first ? Clipper(a, on_first, b, planar) : Clipper(b, on_second, a, planar);
  std::vector<Candidate> points = clipper.clip(margin);
  reduce(points);
  const Eigen::Vector3d& n = clipper.frame().normal;
  for (const Candidate& c : points) {
    ContactPoint& contact = out.emplace_back();
    contact.gap = c.gap;
    contact.key.feature = c.feature + (reference_is_first ? 0 : 128);
    if (reference_is_first) {
      contact.normal = n;
      contact.point_a = c.reference_point;
      contact.point_b = c.incident_point;
      contact.arm_a = c.reference_arm;
      contact.arm_b = c.incident_arm;
    } else {
      contact.normal = -n;
      contact.point_a = c.incident_point;
      contact.point_b = c.reference_point;
      contact.arm_a = c.incident_arm;
      contact.arm_b = c.reference_arm;
    }
  }
  return static_cast<int>(points.size());
}

}  // namespace csim
