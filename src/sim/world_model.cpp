#include "uavip/sim/world_model.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/math.h"
#include "uavip/core/random.h"

namespace uavip::sim {

namespace {

/// Relative tolerance on |edge_u · edge_v| / (|edge_u| |edge_v|) for a rectangle.
constexpr double kOrthogonalityTol = 1e-6;

std::string vecString(const Vec3& v) {
  std::ostringstream os;
  os << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return os.str();
}

/// Rotation by yaw_deg about +z (counter-clockwise seen from above).
Eigen::Matrix3d yawRotation(double yaw_deg) {
  return Eigen::AngleAxisd(yaw_deg * kPi / 180.0, Vec3::UnitZ()).toRotationMatrix();
}

}  // namespace

Vec3 Rect::normal() const { return edge_u.cross(edge_v).normalized(); }

double Rect::area() const { return edge_u.cross(edge_v).norm(); }

double Rect::distance(const Vec3& p) const {
  // Edges are orthogonal (enforced by WorldModel::addPlane), so the closest point
  // has the clamped in-plane coordinates: s = clamp((p − c)·u / |u|², 0, 1), same for t.
  const Vec3 d = p - corner;
  const double uu = edge_u.squaredNorm();
  const double vv = edge_v.squaredNorm();
  const double s = uu > 0.0 ? std::clamp(d.dot(edge_u) / uu, 0.0, 1.0) : 0.0;
  const double t = vv > 0.0 ? std::clamp(d.dot(edge_v) / vv, 0.0, 1.0) : 0.0;
  return (p - (corner + s * edge_u + t * edge_v)).norm();
}

void WorldModel::addPoint(const std::string& name, const Vec3& p) {
  require(p.allFinite(), "world", "point '" + name + "' must be finite, got " + vecString(p));
  points_.push_back({name, p});
}

void WorldModel::addLine(const std::string& name, const Vec3& a, const Vec3& b) {
  require(a.allFinite() && b.allFinite(), "world",
          "line '" + name + "' ends must be finite, got " + vecString(a) + " and " + vecString(b));
  require((b - a).norm() > 0.0, "world",
          "line '" + name + "' must have distinct ends, got " + vecString(a) + " twice");
  segments_.push_back({name, a, b});
}

void WorldModel::addPlane(const Rect& rect) {
  const std::string what = "plane '" + rect.name + "'";
  require(rect.corner.allFinite() && rect.edge_u.allFinite() && rect.edge_v.allFinite(), "world",
          what + " corner and edges must be finite");
  const double lu = rect.edge_u.norm();
  const double lv = rect.edge_v.norm();
  require(lu > 0.0, "world", what + " edge_u must be non-zero, got " + vecString(rect.edge_u));
  require(lv > 0.0, "world", what + " edge_v must be non-zero, got " + vecString(rect.edge_v));
  const double cos_angle = std::abs(rect.edge_u.dot(rect.edge_v)) / (lu * lv);
  if (cos_angle > kOrthogonalityTol) {
    std::ostringstream os;
    os << what << " edges must be orthogonal (|cos| <= " << kOrthogonalityTol << "), got |cos| "
       << cos_angle;
    throw InputError("world: " + os.str());
  }
  rects_.push_back(rect);
}

void WorldModel::addBox(const std::string& name, const Vec3& lo, const Vec3& hi, double yaw_deg) {
  require(lo.allFinite() && hi.allFinite() && std::isfinite(yaw_deg), "world",
          "box '" + name + "' corners and yaw must be finite");
  require((lo.array() < hi.array()).all(), "world",
          "box '" + name + "' needs lo < hi on every axis, got lo " + vecString(lo) + " hi " +
              vecString(hi));
  const Vec3 dx(hi.x() - lo.x(), 0.0, 0.0);
  const Vec3 dy(0.0, hi.y() - lo.y(), 0.0);
  const Vec3 dz(0.0, 0.0, hi.z() - lo.z());
  // Each face's edges are ordered so edge_u × edge_v points out of the box.
  const Rect faces[6] = {
      {name + "/+x", Vec3(hi.x(), lo.y(), lo.z()), dy, dz},  // y × z = +x
      {name + "/-x", lo, dz, dy},                            // z × y = −x
      {name + "/+y", Vec3(lo.x(), hi.y(), lo.z()), dz, dx},  // z × x = +y
      {name + "/-y", lo, dx, dz},                            // x × z = −y
      {name + "/+z", Vec3(lo.x(), lo.y(), hi.z()), dx, dy},  // x × y = +z
      {name + "/-z", lo, dy, dx},                            // y × x = −z
  };
  const Vec3 centre = 0.5 * (lo + hi);
  const Eigen::Matrix3d rot = yawRotation(yaw_deg);
  for (const Rect& f : faces) {
    Rect r = f;
    r.corner = centre + rot * (f.corner - centre);
    r.edge_u = rot * f.edge_u;
    r.edge_v = rot * f.edge_v;
    addPlane(r);
  }
}

void WorldModel::addCrossedPlanes(const std::string& name, const Vec3& center, double width,
                                  double height, double yaw_deg) {
  require(center.allFinite() && std::isfinite(yaw_deg), "world",
          "crossed planes '" + name + "' centre and yaw must be finite");
  requirePositive(width, "world", "crossed planes '" + name + "' width");
  requirePositive(height, "world", "crossed planes '" + name + "' height");
  const Vec3 up(0.0, 0.0, height);
  const char* suffix[2] = {"/a", "/b"};
  for (int k = 0; k < 2; ++k) {
    const Vec3 dir = yawRotation(yaw_deg + 90.0 * k) * Vec3::UnitX();
    Rect r;
    r.name = name + suffix[k];
    r.edge_u = width * dir;
    r.edge_v = up;
    r.corner = center - 0.5 * r.edge_u - 0.5 * r.edge_v;
    addPlane(r);
  }
}

void TreeOptions::validate(const std::string& where) const {
  requirePositive(trunk_height_m, where, "trunk_height_m");
  requirePositive(trunk_width_m, where, "trunk_width_m");
  require(std::isfinite(crown_radius_m) && crown_radius_m >= 0.0, where,
          "crown_radius_m must be >= 0, got " + std::to_string(crown_radius_m));
  require(crown_boxes >= 0 && crown_boxes <= 1000, where,
          "crown_boxes must be in [0, 1000], got " + std::to_string(crown_boxes));
  requirePositive(crown_box_m, where, "crown_box_m");
}

void GrassOptions::validate(const std::string& where) const {
  requirePositive(size_x_m, where, "size_x_m");
  requirePositive(size_y_m, where, "size_y_m");
  require(tufts >= 1 && tufts <= 10000, where,
          "tufts must be in [1, 10000], got " + std::to_string(tufts));
  requirePositive(tuft_height_m, where, "tuft_height_m");
  requirePositive(tuft_width_m, where, "tuft_width_m");
}

void WorldModel::addTree(const std::string& name, const Vec3& base, const TreeOptions& o) {
  o.validate("world: tree '" + name + "'");
  require(base.allFinite(), "world",
          "tree '" + name + "' base must be finite, got " + vecString(base));
  const Vec3 half(0.5 * o.trunk_width_m, 0.5 * o.trunk_width_m, 0.0);
  addBox(name + "/trunk", base - half, base + half + Vec3(0.0, 0.0, o.trunk_height_m));
  // Crown centre one crown radius above the trunk top; centres uniform in the ball
  // by rejection from its cube (draw order fixed, so the layout is seeded).
  const Vec3 crown_centre = base + Vec3(0.0, 0.0, o.trunk_height_m + o.crown_radius_m);
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Vec3 h = Vec3::Constant(0.5 * o.crown_box_m);
  for (int i = 0; i < o.crown_boxes; ++i) {
    Vec3 d;
    do {
      d = drawVec3(unit, rng);
    } while (d.squaredNorm() > 1.0);
    const Vec3 c = crown_centre + o.crown_radius_m * d;
    addBox(name + "/crown" + std::to_string(i), c - h, c + h);
  }
}

void WorldModel::addGrass(const std::string& name, const Vec3& center, const GrassOptions& o) {
  o.validate("world: grass '" + name + "'");
  require(center.allFinite(), "world",
          "grass '" + name + "' center must be finite, got " + vecString(center));
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double hw = 0.5 * o.tuft_width_m;
  for (int i = 0; i < o.tufts; ++i) {
    const double x = center.x() + (unit(rng) - 0.5) * o.size_x_m;
    const double y = center.y() + (unit(rng) - 0.5) * o.size_y_m;
    const double height = o.tuft_height_m * (0.5 + 0.5 * unit(rng));
    addBox(name + "/tuft" + std::to_string(i), Vec3(x - hw, y - hw, center.z()),
           Vec3(x + hw, y + hw, center.z() + height));
  }
}

double WorldModel::distanceToTruth(const Vec3& p) const {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& r : rects_) best = std::min(best, r.distance(p));
  for (const auto& s : segments_) best = std::min(best, pointSegmentDistance(p, s.a, s.b));
  for (const auto& q : points_) best = std::min(best, (p - q.p).norm());
  return best;
}

}  // namespace uavip::sim
