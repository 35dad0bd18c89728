#include "uavip/world/solids.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <utility>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/key_sort.h"
#include "uavip/core/math.h"
#include "uavip/core/voxel_key.h"

// qhull (reentrant), the library behind PCL's ConvexHull, linked through PCL. Last:
// its headers define macros (True, False, FORALLfacets, ...).
#include <libqhull_r/qhull_ra.h>

namespace uavip::world {
namespace {

// ---------------------------------------------------------------- exact distances

/// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection §5.1.5).
Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

double segmentTriangle(const Vec3& a, const Vec3& b, const Vec3& t0, const Vec3& t1, const Vec3& t2,
                       Vec3& q) {
  const Vec3 n = (t1 - t0).cross(t2 - t0);
  const double da = n.dot(a - t0), db = n.dot(b - t0);
  if (n.squaredNorm() > 0.0 && ((da <= 0.0 && db >= 0.0) || (da >= 0.0 && db <= 0.0)) && da != db) {
    // The segment meets the triangle's plane at x: inside the triangle → distance 0.
    const Vec3 x = a + (da / (da - db)) * (b - a);
    if (n.dot((t1 - t0).cross(x - t0)) >= 0.0 && n.dot((t2 - t1).cross(x - t1)) >= 0.0 &&
        n.dot((t0 - t2).cross(x - t2)) >= 0.0) {
      q = x;
      return 0.0;
    }
  }
  // Otherwise the minimum is at an end of the segment or on an edge of the triangle.
  double best = kInf;
  for (const Vec3* p : {&a, &b}) {
    const Vec3 c = closestOnTriangle(*p, t0, t1, t2);
    const double d = (c - *p).norm();
    if (d < best) {
      best = d;
      q = c;
    }
  }
  const std::array<std::pair<const Vec3*, const Vec3*>, 3> edges{
      {{&t0, &t1}, {&t1, &t2}, {&t2, &t0}}};
  for (const auto& [e0, e1] : edges) {
    Vec3 cs, ce;
    const double d = segmentSegmentDistance(a, b, *e0, *e1, &cs, &ce);
    if (d < best) {
      best = d;
      q = ce;
    }
  }
  return best;
}

// ---------------------------------------------------------------- polyhedron

void Polyhedron::finish() {
  Vec3 centre = Vec3::Zero();
  for (const auto& v : vertices) centre += v;
  centre /= static_cast<double>(vertices.size());
  normals.clear();
  offsets.clear();
  ball_centres.clear();
  ball_radii.clear();
  for (auto& t : triangles) {
    const Vec3& a = vertices[static_cast<std::size_t>(t[0])];
    Vec3 n = (vertices[static_cast<std::size_t>(t[1])] - a)
                 .cross(vertices[static_cast<std::size_t>(t[2])] - a);
    if (n.dot(a - centre) < 0.0) {
      std::swap(t[1], t[2]);
      n = -n;
    }
    n.normalize();
    normals.push_back(n);
    offsets.push_back(-n.dot(a));
    Aabb box;
    for (const int v : t) box.extend(vertices[static_cast<std::size_t>(v)]);
    const Vec3 c = 0.5 * (box.min + box.max);
    double r = 0.0;
    for (const int v : t) r = std::max(r, (vertices[static_cast<std::size_t>(v)] - c).norm());
    ball_centres.push_back(c);
    ball_radii.push_back(r * (1.0 + 1e-12) + 1e-12);
  }
}

bool Polyhedron::contains(const Vec3& p) const {
  for (std::size_t i = 0; i < normals.size(); ++i) {
    if (normals[i].dot(p) + offsets[i] > 0.0) return false;
  }
  return true;
}

double Polyhedron::distance(const Vec3& a, const Vec3& b, Vec3& q) const {
  if (contains(a)) {
    q = a;
    return 0.0;
  }
  if (contains(b)) {
    q = b;
    return 0.0;
  }
  // Two exact prunings before the triangle test. (1) The nearest point q of a convex
  // solid to a point s outside lies on a triangle whose plane has s strictly on its
  // outer side (s − q is in the normal cone at q), so a triangle with both ends of
  // the segment on its inner side cannot hold it. (2) A triangle whose bounding
  // ball lies at least `best` from the segment cannot improve on `best`.
  double best = kInf;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    if (normals[i].dot(a) + offsets[i] <= 0.0 && normals[i].dot(b) + offsets[i] <= 0.0) continue;
    if (pointSegmentDistance(ball_centres[i], a, b) - ball_radii[i] > best) continue;
    const auto& t = triangles[i];
    Vec3 c;
    const double d = segmentTriangle(a, b, vertices[static_cast<std::size_t>(t[0])],
                                     vertices[static_cast<std::size_t>(t[1])],
                                     vertices[static_cast<std::size_t>(t[2])], c);
    if (d < best) {
      best = d;
      q = c;
      if (best == 0.0) break;
    }
  }
  return best;
}

Aabb Polyhedron::bounds() const {
  Aabb box;
  for (const auto& v : vertices) box.extend(v);
  return box;
}

Polyhedron prism(const std::vector<Vec3>& top, const Vec3& depth) {
  Polyhedron p;
  const int n = static_cast<int>(top.size());
  for (const auto& v : top) p.vertices.push_back(v);
  for (const auto& v : top) p.vertices.push_back(v - depth);
  for (int i = 1; i + 1 < n; ++i) {
    p.triangles.push_back({0, i, i + 1});
    p.triangles.push_back({n, n + i, n + i + 1});
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    p.triangles.push_back({i, n + i, n + j});
    p.triangles.push_back({i, n + j, j});
  }
  p.finish();
  return p;
}

// ---------------------------------------------------------------- surface slabs

Polyhedron surfaceSlab(const Surface& s, double thickness) {
  const Vec3 n = s.plane.normal.normalized();
  Vec3 u = s.axis_u - s.axis_u.dot(n) * n;
  if (u.norm() < 1e-9) u = n.unitOrthogonal();
  u.normalize();
  const Vec3 v = n.cross(u);
  const Vec3 origin = s.plane.project(s.boundary.empty() ? s.centroid : s.boundary.front());
  std::vector<Eigen::Vector2d> uv;
  for (const auto& p : s.boundary) {
    const Vec3 d = p - origin;
    uv.emplace_back(d.dot(u), d.dot(v));
  }
  const auto h = convexHull2d(uv);  // counter-clockwise, collinear points dropped
  if (h.size() < 3 || polygonTwiceSignedArea2d(h) <= 1e-12) return {};
  std::vector<Vec3> top;
  top.reserve(h.size());
  for (const auto& p : h) top.push_back(origin + p.x() * u + p.y() * v);
  return prism(top, thickness * n);
}

// ---------------------------------------------------------------- obstacle solids

namespace {

/// PCA frame of a point set: centre, right-handed axes (columns) and the extents of
/// the points along them (lo, hi, relative to the centre).
struct PcaFrame {
  Vec3 mean{Vec3::Zero()};
  Eigen::Matrix3d axes{Eigen::Matrix3d::Identity()};
  Vec3 lo{Vec3::Zero()}, hi{Vec3::Zero()};
};

PcaFrame pcaFrame(const PointList& pts) {
  PcaFrame f;
  for (const auto& p : pts) f.mean += p;
  f.mean /= static_cast<double>(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) cov += (p - f.mean) * (p - f.mean).transpose();
  if (pts.size() >= 2) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    if (eig.info() == Eigen::Success) f.axes = eig.eigenvectors();
    if (f.axes.determinant() < 0.0) f.axes.col(2) = -f.axes.col(2);
  }
  f.lo = Vec3::Constant(kInf);
  f.hi = Vec3::Constant(-kInf);
  for (const auto& p : pts) {
    const Vec3 l = f.axes.transpose() * (p - f.mean);
    f.lo = f.lo.cwiseMin(l);
    f.hi = f.hi.cwiseMax(l);
  }
  return f;
}

/// The oriented bounding box of frame `f`, every edge at least `min_edge` long.
Polyhedron orientedBox(PcaFrame f, double min_edge) {
  for (int k = 0; k < 3; ++k) {
    const double grow = std::max(0.0, 0.5 * (min_edge - (f.hi[k] - f.lo[k])));
    f.lo[k] -= grow;
    f.hi[k] += grow;
  }
  std::vector<Vec3> top;  // the face at hi.z, in order around it
  for (const auto& [x, y] : std::array<std::pair<double, double>, 4>{{{f.lo.x(), f.lo.y()},
                                                                      {f.hi.x(), f.lo.y()},
                                                                      {f.hi.x(), f.hi.y()},
                                                                      {f.lo.x(), f.hi.y()}}}) {
    top.push_back(f.mean + f.axes * Vec3(x, y, f.hi.z()));
  }
  return prism(top, (f.hi.z() - f.lo.z()) * f.axes.col(2));
}

/// Triangles of the 3D convex hull of `pts` (indices into `pts`), by qhull in double
/// precision on the points relative to `centre`; empty if qhull fails. qhull's
/// messages go to a memory stream, not to stderr.
std::vector<std::array<int, 3>> hullTriangles(const PointList& pts, const Vec3& centre) {
  std::vector<std::array<int, 3>> tris;
  std::vector<coordT> coords;
  coords.reserve(3 * pts.size());
  for (const auto& p : pts) {
    const Vec3 q = p - centre;
    coords.insert(coords.end(), {q.x(), q.y(), q.z()});
  }
  char* log = nullptr;
  std::size_t log_size = 0;
  FILE* err = open_memstream(&log, &log_size);
  if (err == nullptr) return tris;
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, err);
  // "Qt": triangulated output (done inside qh_new_qhull's error guard).
  char flags[] = "qhull Qt";
  const int code =
      qh_new_qhull(qh, 3, static_cast<int>(pts.size()), coords.data(), False, flags, nullptr, err);
  if (code == 0) {
    facetT* facet;
    FORALLfacets {
      if (qh_setsize(qh, facet->vertices) != 3) {  // not triangulated: give up on the hull
        tris.clear();
        break;
      }
      std::array<int, 3> t{};
      int k = 0;
      vertexT *vertex, **vertexp;
      FOREACHvertex_(facet->vertices) t[static_cast<std::size_t>(k++)] =
          qh_pointid(qh, vertex->point);
      tris.push_back(t);
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  std::fclose(err);
  std::free(log);  // NOLINT: allocated by open_memstream
  return tris;
}

}  // namespace

Polyhedron hullSolid(const PointList& pts, const Vec3& centre) {
  const auto tris = hullTriangles(pts, centre);
  if (tris.size() < 4) return {};
  Polyhedron p;
  std::vector<int> local(pts.size(), -1);
  double extent = 0.0;
  for (const auto& q : pts) extent = std::max(extent, (q - centre).norm());
  const double min_area2 = 1e-12 * extent * extent;  // twice a negligible triangle area [m²]
  for (const auto& t : tris) {
    for (int v : t) {
      if (v < 0 || static_cast<std::size_t>(v) >= pts.size()) return {};
    }
    const Vec3& a = pts[static_cast<std::size_t>(t[0])];
    if ((pts[static_cast<std::size_t>(t[1])] - a)
            .cross(pts[static_cast<std::size_t>(t[2])] - a)
            .norm() <= min_area2) {
      continue;  // a sliver of the triangulation: its edges belong to its neighbours
    }
    std::array<int, 3> lt{};
    for (int k = 0; k < 3; ++k) {
      int& id = local[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])];
      if (id < 0) {
        id = static_cast<int>(p.vertices.size());
        p.vertices.push_back(pts[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])]);
      }
      lt[static_cast<std::size_t>(k)] = id;
    }
    p.triangles.push_back(lt);
  }
  if (p.triangles.size() < 4 || p.vertices.size() < 4) return {};
  for (int round = 0; round < 3; ++round) {
    p.finish();
    Vec3 c = Vec3::Zero();
    for (const auto& v : p.vertices) c += v;
    c /= static_cast<double>(p.vertices.size());
    // Scaling about c by s moves each face plane from height h to s·h above c.
    double scale = 1.0;
    for (std::size_t f = 0; f < p.normals.size(); ++f) {
      const double h = -(p.normals[f].dot(c) + p.offsets[f]);
      if (!(h > 0.0)) return {};  // the centre is not strictly inside: degenerate
      double out = 0.0;
      for (const auto& q : pts) out = std::max(out, p.normals[f].dot(q) + p.offsets[f]);
      if (out > 0.0) scale = std::max(scale, (h + out) / h + 1e-12);
    }
    if (scale == 1.0) return p;
    for (auto& v : p.vertices) v = c + scale * (v - c);
  }
  return {};
}

Polyhedron obstacleSolid(const Obstacle& o, double min_edge) {
  if (o.points.empty()) return {};
  const PcaFrame f = pcaFrame(o.points);
  if (o.points.size() >= 4 && (f.hi - f.lo).minCoeff() >= min_edge) {
    Polyhedron hull = hullSolid(o.points, f.mean);
    if (!hull.triangles.empty()) return hull;
  }
  return orientedBox(f, min_edge);
}

std::vector<Obstacle> obstaclePieces(const Obstacle& o, double edge) {
  if (o.points.empty() || ((o.aabb_max - o.aabb_min).array() <= edge).all()) return {o};
  const VoxelKeyer keyer = VoxelKeyer::forPoints(o.points, edge, "obstacle_piece_m");
  std::vector<std::pair<std::uint64_t, std::size_t>> keyed(o.points.size());
  for (std::size_t i = 0; i < o.points.size(); ++i) keyed[i] = {keyer.key(o.points[i]), i};
  std::sort(keyed.begin(), keyed.end());
  std::vector<Obstacle> pieces;
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].first != keyed[i - 1].first) {
      pieces.emplace_back();
      pieces.back().id = o.id;
    }
    pieces.back().points.push_back(o.points[keyed[i].second]);
  }
  for (auto& piece : pieces) {
    const Aabb box = boundingBox(piece.points);
    piece.aabb_min = box.min;
    piece.aabb_max = box.max;
  }
  return pieces;
}

// ---------------------------------------------------------------- shell samples

namespace {

/// Voxel keys of triangle (p0, p1, p2)'s samples inside `region` (all without one):
/// rows parallel to the longest edge, `spacing` apart along the height and along each
/// row, so the samples grow with the area (a long sliver of a hull gets a few rows,
/// not a lattice over its longest edge).
void sampleTriangle(const std::array<Vec3, 3>& p, double spacing, const VoxelKeyer& keyer,
                    const Aabb* region, std::vector<std::uint64_t>& keys) {
  const auto inRegion = [region](const Vec3& q) {
    return region == nullptr ||
           (((q - region->min).array() >= 0.0).all() && ((region->max - q).array() >= 0.0).all());
  };
  int longest = 0;
  for (int e = 1; e < 3; ++e) {
    if ((p[(e + 1) % 3] - p[e]).squaredNorm() > (p[(longest + 1) % 3] - p[longest]).squaredNorm())
      longest = e;
  }
  const Vec3& a = p[longest];
  const Vec3& b = p[(longest + 1) % 3];
  const Vec3& apex = p[(longest + 2) % 3];
  const Vec3 base = b - a;
  const double height =
      base.squaredNorm() > 0.0 ? (apex - a).cross(base).norm() / base.norm() : (apex - a).norm();
  const int rows = std::max(1, static_cast<int>(std::ceil(height / spacing)));
  for (int r = 0; r <= rows; ++r) {
    const double f = static_cast<double>(r) / rows;
    const Vec3 from = a + f * (apex - a);
    const Vec3 to = b + f * (apex - b);
    const int n = std::max(1, static_cast<int>(std::ceil((to - from).norm() / spacing)));
    for (int j = 0; j <= n; ++j) {
      const Vec3 q = from + (to - from) * (static_cast<double>(j) / n);
      if (inRegion(q)) keys.push_back(keyer.key(q));
    }
  }
}

}  // namespace

PointList shellSamples(const std::vector<Polyhedron>& solids, double spacing,
                       const std::vector<const PointList*>& occupied, const Aabb* region,
                       const TriangleMesh* mesh) {
  requirePositive(spacing, "world", "solid sample spacing");
  const auto meets = [region](const Aabb& b) {
    return region == nullptr || (((b.max - region->min).array() >= 0.0).all() &&
                                 ((region->max - b.min).array() >= 0.0).all());
  };
  Aabb all;
  for (const auto& solid : solids) {
    if (solid.triangles.empty()) continue;
    Aabb b = solid.bounds();
    if (!meets(b)) continue;
    if (region != nullptr) b = Aabb{b.min.cwiseMax(region->min), b.max.cwiseMin(region->max)};
    all.extend(b.min);
    all.extend(b.max);
  }
  // A mesh's triangles that meet the region, each with its box.
  std::vector<std::uint32_t> mesh_triangles;
  if (mesh != nullptr) {
    for (std::size_t i = 0; i < mesh->triangles.size(); ++i) {
      Aabb b;
      for (const std::uint32_t v : mesh->triangles[i]) b.extend(mesh->vertices[v]);
      if (!meets(b)) continue;
      if (region != nullptr) b = Aabb{b.min.cwiseMax(region->min), b.max.cwiseMin(region->max)};
      all.extend(b.min);
      all.extend(b.max);
      mesh_triangles.push_back(static_cast<std::uint32_t>(i));
    }
  }
  if (all.empty()) return {};
  const VoxelKeyer keyer(all.min, all.max, spacing, "solid sample spacing");
  std::vector<std::uint64_t> keys;
  for (const auto& solid : solids) {
    if (solid.triangles.empty() || !meets(solid.bounds())) continue;
    for (const auto& t : solid.triangles) {
      sampleTriangle({solid.vertices[static_cast<std::size_t>(t[0])],
                      solid.vertices[static_cast<std::size_t>(t[1])],
                      solid.vertices[static_cast<std::size_t>(t[2])]},
                     spacing, keyer, region, keys);
    }
  }
  for (const std::uint32_t i : mesh_triangles) {
    const auto& t = mesh->triangles[i];
    sampleTriangle({mesh->vertices[t[0]], mesh->vertices[t[1]], mesh->vertices[t[2]]}, spacing,
                   keyer, region, keys);
  }
  sortUniqueKeys(keys);
  // Voxels the measured points already fill add nothing.
  std::vector<std::uint64_t> measured;
  const Aabb inside{all.min - Vec3::Constant(spacing), all.max + Vec3::Constant(spacing)};
  for (const PointList* cloud : occupied) {
    for (const auto& q : *cloud) {
      if (((q - inside.min).array() >= 0.0).all() && ((q - inside.max).array() <= 0.0).all()) {
        measured.push_back(keyer.key(q));
      }
    }
  }
  sortUniqueKeys(measured);
  PointList out;
  out.reserve(keys.size());
  // Both ascending: one merge-like walk.
  auto m = measured.begin();
  for (const auto k : keys) {
    while (m != measured.end() && *m < k) ++m;
    if (m == measured.end() || *m != k) out.push_back(keyer.centre(k));
  }
  return out;
}

Polyhedron keepOutSolid(const KeepOut& k) {
  const double h = k.size.z();
  const Vec3 top_centre = k.center + Vec3(0.0, 0.0, 0.5 * h);
  std::vector<Vec3> top;
  if (k.shape == KeepOut::Shape::Cylinder) {
    constexpr int kSides = 32;
    const double r = 0.5 * k.size.x() / std::cos(kPi / kSides);
    for (int i = 0; i < kSides; ++i) {
      const double a = 2.0 * kPi * i / kSides;
      top.push_back(top_centre + Vec3(r * std::cos(a), r * std::sin(a), 0.0));
    }
  } else {
    const double yaw = k.yaw_deg * kDegToRad;
    const Vec3 ex(std::cos(yaw), std::sin(yaw), 0.0);
    const Vec3 ey(-std::sin(yaw), std::cos(yaw), 0.0);
    const double a = 0.5 * k.size.x();
    const double b = 0.5 * k.size.y();
    top = {top_centre - a * ex - b * ey, top_centre + a * ex - b * ey, top_centre + a * ex + b * ey,
           top_centre - a * ex + b * ey};
  }
  return prism(top, Vec3(0.0, 0.0, h));
}

PointList interiorSamples(const Polyhedron& solid, double spacing, const Aabb* region) {
  PointList out;
  if (solid.triangles.empty() || !(spacing > 0.0)) return out;
  Aabb box = solid.bounds();
  if (region != nullptr) {
    box.min = box.min.cwiseMax(region->min);
    box.max = box.max.cwiseMin(region->max);
  }
  if (box.empty()) return out;
  const Eigen::Array3d steps = ((box.max - box.min) / spacing).array().floor() + 1.0;
  if (steps.prod() > 5e7) return out;  // the shell still marks it; a grid that fine is refused
  for (int i = 0; i < static_cast<int>(steps.x()); ++i) {
    for (int j = 0; j < static_cast<int>(steps.y()); ++j) {
      for (int k = 0; k < static_cast<int>(steps.z()); ++k) {
        const Vec3 p = box.min + spacing * Vec3(i, j, k);
        if (solid.contains(p)) out.push_back(p);
      }
    }
  }
  return out;
}

}  // namespace uavip::world
