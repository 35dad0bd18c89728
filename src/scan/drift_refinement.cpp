#include "uavip/scan/drift_refinement.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/voxel_key.h"
#include "uavip/scan/station_assembler.h"

namespace uavip::scan {
namespace {

using Mat3 = Eigen::Matrix3d;

/// Each point's place in the node chain: δ(t) = (1 − u)·δ_k + u·δ_{k+1}.
struct NodeWeight {
  int k{0};
  double u{0.0};
};

NodeWeight nodeWeight(const std::vector<double>& nodes, double t) {
  if (t <= nodes.front()) return {0, 0.0};
  if (t >= nodes.back()) return {static_cast<int>(nodes.size()) - 2, 1.0};
  const auto j =
      static_cast<std::size_t>(std::upper_bound(nodes.begin(), nodes.end(), t) - nodes.begin());
  return {static_cast<int>(j) - 1, (t - nodes[j - 1]) / std::max(1e-12, nodes[j] - nodes[j - 1])};
}

/// The points of one refinement: fixed parts, and the positions of the current step.
struct Problem {
  std::vector<Vec3> base;  ///< offset + odometry T(t) [m]
  std::vector<Vec3> p;     ///< base + δ(t) [m]
  std::vector<double> w;   ///< effective pairs per point
  std::vector<NodeWeight> nw;
  std::vector<char> end;        ///< in the loop closure's end window
  std::vector<int> vertical;    ///< indices of the vertical scanner's points
  std::vector<int> horizontal;  ///< indices of the horizontal scanner's points
  std::size_t nodes{0};
  DriftTuning tuning;
};

/// Points binned by cell: order[start[c] .. start[c+1]) are cell c's point indices.
struct Cells {
  std::vector<int> order;
  std::vector<int> start;
};

/// Bins p[subset] into voxels (or columns) of edge cell_m.
Cells binPoints(const std::vector<Vec3>& p, const std::vector<int>& subset, double cell_m,
                bool column) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const int i : subset) {
    lo = lo.cwiseMin(p[static_cast<std::size_t>(i)]);
    hi = hi.cwiseMax(p[static_cast<std::size_t>(i)]);
  }
  if (subset.empty()) lo = hi = Vec3::Zero();
  const AssemblerOptions defaults;
  const VoxelKeyer keyer(
      lo, hi, cell_m,
      "assembly." + AssemblerOptions::table().find(defaults, &defaults.drift_voxel_m)->key);
  // A column is the voxel key with z dropped.
  const auto cellKey = [&](const Vec3& q) {
    const auto c = keyer.cell(q);
    return VoxelKeyer::pack(c[0], c[1], column ? 0 : c[2]);
  };
  std::unordered_map<std::uint64_t, int> index;
  index.reserve(subset.size() / 4 + 16);
  std::vector<int> cell_of(subset.size());
  std::vector<int> count;
  for (std::size_t j = 0; j < subset.size(); ++j) {
    const auto [it, added] = index.try_emplace(cellKey(p[static_cast<std::size_t>(subset[j])]),
                                               static_cast<int>(count.size()));
    if (added) count.push_back(0);
    cell_of[j] = it->second;
    ++count[static_cast<std::size_t>(it->second)];
  }
  Cells c;
  c.start.assign(count.size() + 1, 0);
  for (std::size_t k = 0; k < count.size(); ++k) c.start[k + 1] = c.start[k] + count[k];
  c.order.resize(subset.size());
  std::vector<int> fill(c.start.begin(), c.start.end() - 1);
  for (std::size_t j = 0; j < subset.size(); ++j)
    c.order[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_of[j])]++)] = subset[j];
  return c;
}

/// A cell's weighted centroid and scatter, the scatter pooled within segments (each
/// segment about its own centroid): a segment displaced along the normal, beside
/// another one in the cell, would otherwise tilt the fitted plane until the
/// displacement vanished from the residuals. A column's scatter is that of the
/// points' xy (z row and column zero).
struct Scatter {
  Vec3 centroid{Vec3::Zero()};
  Mat3 cov{Mat3::Zero()};
};

/// Scratch space of pooledScatter: per segment Σw, Σw·p, Σw·p pᵀ.
struct SegmentSums {
  explicit SegmentSums(std::size_t segments)
      : w(segments, 0.0), s1(segments, Vec3::Zero()), s2(segments, Mat3::Zero()) {}
  std::vector<double> w;
  std::vector<Vec3> s1;
  std::vector<Mat3> s2;
  std::vector<int> touched;
};

/// The scatter of the points idx[0 .. n) (see Scatter).
Scatter pooledScatter(const Problem& pb, const int* idx, int n, bool column, SegmentSums& sums) {
  double sw = 0.0;
  Scatter out;
  for (int j = 0; j < n; ++j) {
    const auto i = static_cast<std::size_t>(idx[j]);
    const auto k = static_cast<std::size_t>(pb.nw[i].k);
    const Vec3 q = column ? Vec3(pb.p[i].x(), pb.p[i].y(), 0.0) : pb.p[i];
    if (sums.w[k] == 0.0) sums.touched.push_back(static_cast<int>(k));
    sums.w[k] += pb.w[i];
    sums.s1[k] += pb.w[i] * q;
    sums.s2[k] += pb.w[i] * q * q.transpose();
    sw += pb.w[i];
    out.centroid += pb.w[i] * pb.p[i];
  }
  out.centroid /= sw;
  for (const int k : sums.touched) {
    const auto u = static_cast<std::size_t>(k);
    out.cov += sums.s2[u] - sums.s1[u] * sums.s1[u].transpose() / sums.w[u];
    sums.w[u] = 0.0;
    sums.s1[u].setZero();
    sums.s2[u].setZero();
  }
  sums.touched.clear();
  out.cov /= sw;
  return out;
}

/// What a voxel of the vertical scanner's points is.
enum class Surface { None, Level, Upright, Sloped };

/// Classifies a voxel by its scatter; `normal` is set for Level (exactly ±z) and Sloped.
/// Gravity-aligned surfaces are snapped: the IMU's attitude noise tilts a fitted
/// normal by a degree or two, and a tilted floor normal would turn the floor's large
/// z information into spurious horizontal forces (or a wall's into vertical ones).
Surface classifyVoxel(const Scatter& s, const DriftTuning& tuning, Vec3& normal) {
  Eigen::SelfAdjointEigenSolver<Mat3> es;
  es.computeDirect(s.cov);
  const Vec3 ev = es.eigenvalues();
  const double thickness = tuning.max_thickness_m;
  if (!(ev(0) >= 0.0) || ev(0) > thickness * thickness || !(ev(0) < tuning.flat_ratio * ev(1)))
    return Surface::None;
  normal = es.eigenvectors().col(0);
  const double snap = tuning.gravity_aligned_deg * kDegToRad;
  if (std::abs(normal.z()) >= std::cos(snap)) {
    normal = Vec3::UnitZ();
    return Surface::Level;
  }
  return std::abs(normal.z()) <= std::sin(snap) ? Surface::Upright : Surface::Sloped;
}

/// The horizontal normal of a column whose points lie on a straight line in xy, or zero.
Vec3 columnNormal(const Scatter& s, const DriftTuning& tuning) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es;
  es.computeDirect(s.cov.topLeftCorner<2, 2>());
  const Eigen::Vector2d ev = es.eigenvalues();
  const double thickness = tuning.max_thickness_m;
  if (!(ev(0) >= 0.0) || ev(0) > thickness * thickness || !(ev(0) < tuning.flat_ratio * ev(1)))
    return Vec3::Zero();
  return Vec3(es.eigenvectors()(0, 0), es.eigenvectors()(1, 0), 0.0);
}

/// Normal equations of one iteration over all nodes (node 0 included), and those of
/// the loop closure: the end window moved alone against the rest of the sweep.
struct System {
  Eigen::MatrixXd h;
  Eigen::VectorXd g;
  std::size_t planes{0};
  Mat3 h_loop{Mat3::Zero()};
  Vec3 g_loop{Vec3::Zero()};
};

/// One plane's sufficient statistics over nodes (the offset eliminated: see accumulate).
struct VoxelStats {
  explicit VoxelStats(std::size_t nodes)
      : s(nodes, 0.0), gk(nodes, 0.0), md(nodes, 0.0), mo(nodes, 0.0), mark(nodes, 0) {}
  void reset() {
    for (const int k : touched) {
      const auto u = static_cast<std::size_t>(k);
      s[u] = gk[u] = md[u] = mo[u] = 0.0;
      mark[u] = 0;
    }
    touched.clear();
    w = r = w_last = r_last = 0.0;
  }
  void touch(int k) {
    if (!mark[static_cast<std::size_t>(k)]) {
      mark[static_cast<std::size_t>(k)] = 1;
      touched.push_back(k);
    }
  }
  std::vector<double> s, gk, md, mo;  // Σω·a_k, Σω·a_k·r, Σω·a_k², Σω·a_k·a_{k+1}
  std::vector<char> mark;
  std::vector<int> touched;
  double w{0.0}, r{0.0};            // Σω, Σω·r
  double w_last{0.0}, r_last{0.0};  // the same over the end window's points
};

/// Adds one point's residual r with weight ω at node weight nw.
void addPoint(VoxelStats& v, const NodeWeight& nw, double omega, double r, bool end) {
  const int k = nw.k;
  const double a0 = 1.0 - nw.u, a1 = nw.u;
  v.touch(k);
  v.touch(k + 1);
  const auto u0 = static_cast<std::size_t>(k), u1 = u0 + 1;
  v.s[u0] += omega * a0;
  v.s[u1] += omega * a1;
  v.gk[u0] += omega * a0 * r;
  v.gk[u1] += omega * a1 * r;
  v.md[u0] += omega * a0 * a0;
  v.md[u1] += omega * a1 * a1;
  v.mo[u0] += omega * a0 * a1;
  v.w += omega;
  v.r += omega * r;
  if (end) {
    v.w_last += omega;
    v.r_last += omega * r;
  }
}

/// Adds a plane's statistics (normal n) to the system. With the plane offset d
/// eliminated, Σ ω (r + a·Δ·n − d)² has the Hessian (M − s sᵀ/W) ⊗ n nᵀ and the
/// gradient (g − s·R/W) ⊗ n in the node corrections Δ (M_kl = Σω·a_k·a_l, s_k =
/// Σω·a_k, W = Σω, R = Σω·r). The loop closure moves the end window (a) alone against
/// the rest (b): Hessian W_a·W_b/W·n nᵀ, gradient the same factor times
/// (mean r_a − mean r_b)·n.
void accumulate(const VoxelStats& v, const Vec3& n, bool loop_only, System& sys) {
  if (v.w <= 0.0) return;
  const Mat3 nn = n * n.transpose();
  const double w_other = v.w - v.w_last;
  if (v.w_last > 0.0 && w_other > 0.0) {
    const double f = v.w_last * w_other / v.w;
    sys.h_loop += f * nn;
    sys.g_loop += f * (v.r_last / v.w_last - (v.r - v.r_last) / w_other) * n;
  }
  if (loop_only) return;
  const double rbar = v.r / v.w;
  for (const int k : v.touched) {
    const auto uk = static_cast<std::size_t>(k);
    const Eigen::Index ik = k;
    sys.g.segment<3>(3 * ik) += (v.gk[uk] - v.s[uk] * rbar) * n;
    for (const int l : v.touched) {
      const auto ul = static_cast<std::size_t>(l);
      double m = l == k ? v.md[uk] : l == k + 1 ? v.mo[uk] : k == l + 1 ? v.mo[ul] : 0.0;
      m -= v.s[uk] * v.s[ul] / v.w;
      sys.h.block<3, 3>(3 * ik, 3 * static_cast<Eigen::Index>(l)) += m * nn;
    }
  }
}

/// Adds one plane's residuals n·(p − c) (Cauchy-weighted) to the system.
void addPlane(const Problem& pb, const std::vector<DriftPoint>& pts, const int* idx, int n,
              const Vec3& normal, const Vec3& centroid, bool loop_only, VoxelStats& stats,
              System& sys) {
  ++sys.planes;
  stats.reset();
  for (int j = 0; j < n; ++j) {
    const auto i = static_cast<std::size_t>(idx[j]);
    const double r = normal.dot(pb.p[i] - centroid);
    const double scale = pb.tuning.robust_sigmas * pts[i].sigma_m;
    addPoint(stats, pb.nw[i], pb.w[i] / (1.0 + (r / scale) * (r / scale)), r, pb.end[i] != 0);
  }
  accumulate(stats, normal, loop_only, sys);
}

/// Builds the normal equations for the points at their current positions: voxels of
/// the vertical scanner's points give level and sloped planes; points on upright
/// planes join the horizontal scanner's points in columns (xy cells through all
/// heights), where an upright face is one line whatever the height it was seen at,
/// so that every segment that saw a face, with either scanner, meets every other.
System buildSystem(const Problem& pb, const std::vector<DriftPoint>& pts, double voxel_m,
                   bool loop_only) {
  System sys;
  if (!loop_only) {
    sys.h = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(3 * pb.nodes),
                                  static_cast<Eigen::Index>(3 * pb.nodes));
    sys.g = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(3 * pb.nodes));
  }
  VoxelStats stats(pb.nodes);
  SegmentSums sums(pb.nodes);
  std::vector<int> upright = pb.horizontal;
  const Cells vox = binPoints(pb.p, pb.vertical, voxel_m, false);
  for (std::size_t v = 0; v + 1 < vox.start.size(); ++v) {
    const int n = vox.start[v + 1] - vox.start[v];
    if (n < pb.tuning.min_cell_points) continue;
    const int* idx = vox.order.data() + vox.start[v];
    const Scatter s = pooledScatter(pb, idx, n, false, sums);
    Vec3 normal;
    const Surface kind = classifyVoxel(s, pb.tuning, normal);
    if (kind == Surface::Upright) upright.insert(upright.end(), idx, idx + n);
    if (kind == Surface::Level || kind == Surface::Sloped)
      addPlane(pb, pts, idx, n, normal, s.centroid, loop_only, stats, sys);
  }
  const Cells cols = binPoints(pb.p, upright, voxel_m, true);
  for (std::size_t c = 0; c + 1 < cols.start.size(); ++c) {
    const int n = cols.start[c + 1] - cols.start[c];
    if (n < pb.tuning.min_cell_points) continue;
    const int* idx = cols.order.data() + cols.start[c];
    const Scatter s = pooledScatter(pb, idx, n, true, sums);
    const Vec3 normal = columnNormal(s, pb.tuning);
    if (normal.squaredNorm() > 0.0)
      addPlane(pb, pts, idx, n, normal, s.centroid, loop_only, stats, sys);
  }
  return sys;
}

/// Smoothness prior λ·|δ_{k+1} − δ_k|² on consecutive nodes.
void addSmoothness(const std::vector<Vec3>& delta, double lambda, System& sys) {
  for (std::size_t k = 0; k + 1 < delta.size(); ++k) {
    const auto a = static_cast<Eigen::Index>(3 * k), b = a + 3;
    const Vec3 d = delta[k + 1] - delta[k];
    sys.h.block<3, 3>(a, a) += lambda * Mat3::Identity();
    sys.h.block<3, 3>(b, b) += lambda * Mat3::Identity();
    sys.h.block<3, 3>(a, b) -= lambda * Mat3::Identity();
    sys.h.block<3, 3>(b, a) -= lambda * Mat3::Identity();
    sys.g.segment<3>(a) -= lambda * d;
    sys.g.segment<3>(b) += lambda * d;
  }
}

/// The fixed parts of every point: odometry position, weight, node weight, window.
Problem makeProblem(const std::vector<DriftPoint>& points, const TranslationTrack& track,
                    const std::vector<double>& node_times_s, double loop_start_s,
                    const DriftTuning& tuning) {
  Problem pb;
  pb.tuning = tuning;
  const double unit = tuning.unit_sigma_m;
  pb.nodes = node_times_s.size();
  pb.base.resize(points.size());
  pb.p.resize(points.size());
  pb.w.resize(points.size());
  pb.nw.resize(points.size());
  pb.end.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    pb.base[i] = points[i].offset + track.at(points[i].t_s);
    pb.w[i] = std::min(1.0, (unit / points[i].sigma_m) * (unit / points[i].sigma_m));
    pb.nw[i] = nodeWeight(node_times_s, points[i].t_s);
    pb.end[i] = points[i].t_s >= loop_start_s ? 1 : 0;
    (points[i].horizontal ? pb.horizontal : pb.vertical).push_back(static_cast<int>(i));
  }
  return pb;
}

/// The sweep's information per direction: Σ over nodes 1… of each node's own 3×3
/// block of the data's normal equations [effective pairs].
Mat3 sweepInformation(const System& sys, std::size_t nodes) {
  Mat3 info = Mat3::Zero();
  for (std::size_t k = 1; k < nodes; ++k)
    info += sys.h.block<3, 3>(static_cast<Eigen::Index>(3 * k), static_cast<Eigen::Index>(3 * k));
  return info;
}

/// Removes from every node's step the directions the whole sweep does not observe
/// (fewer than min_direction_information effective pairs): there the smoothness prior
/// alone would let the chain, anchored only at its first node, follow the slightest
/// force (a tilted normal's leak); the odometry is kept instead.
void freezeUnobserved(const Mat3& information, double min_information, Eigen::VectorXd& step) {
  const Eigen::SelfAdjointEigenSolver<Mat3> es(information);
  for (int c = 0; c < 3; ++c) {
    if (es.eigenvalues()(c) >= min_information) continue;
    const Vec3 e = es.eigenvectors().col(c);
    for (Eigen::Index k = 0; k + 2 < step.size(); k += 3)
      step.segment<3>(k) -= e.dot(step.segment<3>(k)) * e;
  }
}

/// Positions with the corrections δ at the nodes.
void placePoints(Problem& pb, const std::vector<Vec3>& delta) {
  for (std::size_t i = 0; i < pb.base.size(); ++i) {
    const auto k = static_cast<std::size_t>(pb.nw[i].k);
    pb.p[i] = pb.base[i] + (1.0 - pb.nw[i].u) * delta[k] + pb.nw[i].u * delta[k + 1];
  }
}

}  // namespace

Vec3 TranslationTrack::at(double t) const {
  if (times_s.empty()) return Vec3::Zero();
  if (t <= times_s.front()) return positions.front();
  if (t >= times_s.back()) return positions.back();
  const auto j = static_cast<std::size_t>(std::upper_bound(times_s.begin(), times_s.end(), t) -
                                          times_s.begin());
  const double u = (t - times_s[j - 1]) / std::max(1e-12, times_s[j] - times_s[j - 1]);
  return (1.0 - u) * positions[j - 1] + u * positions[j];
}

Vec3 DriftRefinement::at(double t) const {
  if (node_times_s.size() < 2) return Vec3::Zero();
  const NodeWeight nw = nodeWeight(node_times_s, t);
  const auto k = static_cast<std::size_t>(nw.k);
  return (1.0 - nw.u) * corrections_m[k] + nw.u * corrections_m[k + 1];
}

std::vector<double> sweptYawDeg(const std::vector<double>& yaw_rad) {
  std::vector<double> swept(yaw_rad.size(), 0.0);
  for (std::size_t i = 1; i < yaw_rad.size(); ++i) {
    swept[i] = swept[i - 1] + std::abs(wrapAngle(yaw_rad[i] - yaw_rad[i - 1])) * kRadToDeg;
  }
  return swept;
}

double timeAtSweptDeg(const std::vector<double>& times_s, const std::vector<double>& swept_deg,
                      double target_deg) {
  if (times_s.empty()) return 0.0;
  if (target_deg <= swept_deg.front()) return times_s.front();
  if (target_deg >= swept_deg.back()) return times_s.back();
  const auto j = static_cast<std::size_t>(
      std::lower_bound(swept_deg.begin(), swept_deg.end(), target_deg) - swept_deg.begin());
  const double u =
      (target_deg - swept_deg[j - 1]) / std::max(1e-12, swept_deg[j] - swept_deg[j - 1]);
  return times_s[j - 1] + u * (times_s[j] - times_s[j - 1]);
}

std::vector<double> segmentNodeTimes(const std::vector<double>& times_s,
                                     const std::vector<double>& swept_deg, double segment_deg) {
  if (times_s.empty()) return {};
  const int segments = std::max(1, static_cast<int>(std::lround(swept_deg.back() / segment_deg)));
  std::vector<double> nodes{times_s.front()};
  for (int s = 1; s < segments; ++s) {
    const double t = timeAtSweptDeg(times_s, swept_deg, swept_deg.back() * s / segments);
    if (t > nodes.back() && t < times_s.back()) nodes.push_back(t);
  }
  if (times_s.back() > nodes.back()) nodes.push_back(times_s.back());
  return nodes;
}

void DriftTuning::validate(const std::string& where) const {
  requireThat(min_cell_points >= 3, where, "min_cell_points", ">= 3", min_cell_points);
  requireThat(flat_ratio > 0.0 && flat_ratio <= 1.0, where, "flat_ratio", "in (0, 1]", flat_ratio);
  requirePositive(max_thickness_m, where, "max_thickness_m");
  requireThat(gravity_aligned_deg >= 0.0 && gravity_aligned_deg < 45.0, where,
              "gravity_aligned_deg", "in [0, 45)", gravity_aligned_deg);
  requirePositive(unit_sigma_m, where, "unit_sigma_m");
  requirePositive(robust_sigmas, where, "robust_sigmas");
  requireThat(std::isfinite(min_loop_information) && min_loop_information >= 0.0, where,
              "min_loop_information", ">= 0", min_loop_information);
  requireThat(std::isfinite(min_direction_information) && min_direction_information >= 0.0, where,
              "min_direction_information", ">= 0", min_direction_information);
}

DriftRefinement refineDrift(const std::vector<DriftPoint>& points, const TranslationTrack& track,
                            const std::vector<double>& node_times_s, double loop_start_s,
                            const DriftRefinementOptions& options) {
  DriftRefinement out;
  out.node_times_s = node_times_s;
  out.corrections_m.assign(node_times_s.size(), Vec3::Zero());
  if (node_times_s.size() < 2 || points.empty()) return out;
  const DriftTuning& tn = options.tuning;
  tn.validate("drift refinement tuning");
  Problem pb = makeProblem(points, track, node_times_s, loop_start_s, tn);
  const double lambda =
      (tn.unit_sigma_m / options.smoothness_m) * (tn.unit_sigma_m / options.smoothness_m);
  const auto m = static_cast<Eigen::Index>(3 * (pb.nodes - 1));
  for (int it = 0; it < options.iterations; ++it) {
    placePoints(pb, out.corrections_m);
    System sys = buildSystem(pb, points, options.voxel_m, false);
    const Mat3 observed = sweepInformation(sys, pb.nodes);
    addSmoothness(out.corrections_m, lambda, sys);
    // δ_0 = 0 (the station frame's origin): solve for nodes 1….
    Eigen::VectorXd step = -sys.h.bottomRightCorner(m, m).ldlt().solve(sys.g.tail(m));
    if (!step.allFinite()) break;
    freezeUnobserved(observed, tn.min_direction_information, step);
    for (std::size_t k = 1; k < pb.nodes; ++k)
      out.corrections_m[k] += step.segment<3>(static_cast<Eigen::Index>(3 * (k - 1)));
    out.planes = sys.planes;
    out.iterations = it + 1;
  }
  // Loop closure of the result: the end window moved alone onto the rest of the
  // sweep. Each point counts for the beams it was sampled from, so the information
  // is in pairs at the scanners' full resolution.
  placePoints(pb, out.corrections_m);
  for (std::size_t i = 0; i < points.size(); ++i) pb.w[i] *= points[i].beams;
  const System fin = buildSystem(pb, points, options.voxel_m, true);
  const Eigen::SelfAdjointEigenSolver<Mat3> es(fin.h_loop);
  out.loop_closure_information = std::max(0.0, es.eigenvalues()(0));
  if (out.loop_closure_information >= tn.min_loop_information)
    out.loop_closure_m = fin.h_loop.ldlt().solve(fin.g_loop).norm();
  return out;
}

}  // namespace uavip::scan
