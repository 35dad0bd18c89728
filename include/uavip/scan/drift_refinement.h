#pragma once
/// \file
/// Stage 1 (paper §II-A), drift refinement: every beam of a station's sweep, from
/// both scanners, joins one estimate of the translation drift T(t), so that drift is
/// corrected in every direction some surface fixes, not only in those the horizontal
/// scanner's plane happens to cut.
///
/// Why: the horizontal odometry (station_assembler.h) matches each horizontal scan to
/// a keyframe map. Under a bridge deck the horizontal scanner may see one wall
/// direction only (the other drifts unseen), or nothing in the first keyframe (then
/// every scan fails and T stays 0), while the vertical scanner sees the deck
/// underside, the piers and the ground all around.
///
/// Model: the sweep is cut into segments of about drift_segment_deg of yaw; the
/// correction δ(t) added to the odometry's T(t) is linear in time between nodes at
/// the segment ends, δ = 0 at the first node (the station frame's origin). Rotation
/// stays the IMU's. Each iteration places every point with T + δ and solves one
/// linear least-squares problem over the 3·nodes unknowns: point-to-plane residuals,
/// a smoothness prior between consecutive nodes; the planes are refitted from the
/// corrected points between iterations.
///
/// Planes (a voxel plane adjustment in the manner of BALM, Liu & Zhang, RA-L 2021,
/// translation only, rather than k-d-tree normals per point: one hash pass per
/// iteration over ~10⁵ points, and each plane's offset is eliminated in closed form
/// from sufficient statistics per node):
///  - voxels of the vertical scanner's points give level and sloped planes. A plane
///    within 10° of level or upright is snapped to it: the IMU's attitude noise tilts
///    a fitted normal by a degree or two, and a floor normal so tilted turns the
///    floor's large z information into spurious horizontal forces;
///  - the points of upright voxels join the horizontal scanner's points in columns
///    (xy cells through all heights) fitted with a line: an upright face is one line
///    whatever the height it was seen at, so a pier face seen by the vertical scanner
///    at one yaw meets the same face seen by the horizontal scanner at every other.
///    (Matching vertical scans only with each other in 3D voxels was tried first:
///    two yaws see a wall side by side, never overlapping, and the plane's own
///    error then biases their offset; the sweep drifted by decimetres.)
/// A cell's scatter is pooled within segments, so that a displaced segment does not
/// tilt the fitted plane until its displacement vanishes from the residuals.
///
/// Directions the whole sweep fixes with fewer than 10 effective pairs (a floor and
/// one wall: along the wall) are not corrected: there the smoothness prior alone
/// would let the chain, anchored at its first node only, follow the slightest force.
///
/// Loop closure: after the last iteration, the end window (the caller's: the last
/// 30° of yaw) moved alone onto the planes the rest of the sweep saw.
///
/// Effective pairs: a point with 1.5 cm of noise counts 1, a noisier one (far: the
/// IMU's attitude error grows with range) (1.5 cm / σ)², each times its Cauchy weight.

#include <cstddef>
#include <string>
#include <vector>

#include "uavip/core/types.h"

namespace uavip::scan {

/// The UAV centre's translation over time: samples, linear between them, clamped
/// at the ends; (0, 0, 0) without samples.
struct TranslationTrack {
  std::vector<double> times_s;  ///< increasing [s]
  std::vector<Vec3> positions;  ///< station frame [m]
  /// Translation at time t [s].
  Vec3 at(double t_s) const;
};

/// One beam for the refinement: where it ended relative to the UAV centre in the
/// station frame (IMU attitude applied: x − T(t) of eq. (2)), when, and how much it counts.
struct DriftPoint {
  Vec3 offset{Vec3::Zero()};  ///< R(t)·(body_T_scanner·x*) [m]
  double t_s{0.0};            ///< beam time [s]
  double sigma_m{0.01};       ///< expected position noise of the point (range and attitude) [m]
  bool horizontal{false};  ///< from the horizontal scanner (its lines may stand for vertical faces)
  double beams{1.0};       ///< raw beams the point stands for (the sampling stride), for the loop
                           ///< closure's information
};

/// uavip's own tuning of the refinement (AssemblerTuning::drift); the defaults were
/// measured on the simulated sweeps. Not read from YAML.
struct DriftTuning {
  int min_cell_points{6};  ///< a voxel or column needs this many points to give a plane
  /// Planar (voxel) or straight (column): the smallest scatter eigenvalue below this
  /// fraction of the next one.
  double flat_ratio{0.1};
  /// Cells thicker than this (√ smallest scatter eigenvalue) are not planes [m].
  double max_thickness_m{0.05};
  /// Within this angle of level a plane is level, of upright upright [deg].
  double gravity_aligned_deg{10.0};
  /// A point with this noise counts as one effective pair; noisier ones as (this/σ)² [m].
  double unit_sigma_m{0.015};
  double robust_sigmas{3.0};  ///< Cauchy scale of a residual, in σ of its point
  /// Effective pairs the least constrained direction needs for a loop-closure figure.
  double min_loop_information{10.0};
  /// A direction the whole sweep fixes with fewer effective pairs is not corrected.
  double min_direction_information{10.0};

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where) const;
};

/// Options of the refinement (AssemblerOptions::refine_drift and the drift_* fields).
struct DriftRefinementOptions {
  int iterations{3};           ///< least-squares steps (planes refitted between them), >= 1
  double voxel_m{0.5};         ///< voxel and column edge [m]
  double smoothness_m{0.015};  ///< σ of the correction's change from one node to the next [m]
  DriftTuning tuning;          ///< uavip's own tuning (above)
};

/// The correction δ(t) to add to the odometry's T(t), and the loop closure it implies.
struct DriftRefinement {
  std::vector<double> node_times_s;  ///< segment ends [s]; δ = 0 at the first
  std::vector<Vec3> corrections_m;   ///< δ at each node [m]
  /// Loop closure (paper §III) of the refined sweep: the translation that would bring
  /// its end window (the points from loop_start_s on), moved alone, onto the rest of
  /// the sweep, which starts at its start [m]; −1 when the least constrained direction
  /// has fewer than 10 effective pairs.
  double loop_closure_m{-1.0};
  /// Effective pairs fixing the least constrained direction of that fit, each point
  /// counted for its `beams` (so at the scanners' full resolution).
  double loop_closure_information{0.0};
  std::size_t planes{0};  ///< planes (voxels and columns) of the last iteration
  int iterations{0};
  /// δ at time t [s]: linear between nodes, clamped at the ends [m].
  Vec3 at(double t_s) const;
};

/// The yaw swept since the first sample [deg]: |Δyaw| summed, so a turn of 360°
/// ends at 360 whichever way it turned.
std::vector<double> sweptYawDeg(const std::vector<double>& yaw_rad);

/// The time at which `swept_deg` (of samples at `times_s`) reaches target_deg,
/// linear between samples, clamped to the first and last time [s].
double timeAtSweptDeg(const std::vector<double>& times_s, const std::vector<double>& swept_deg,
                      double target_deg);

/// Node times for segments of about segment_deg of swept yaw, equal shares of the
/// whole sweep; the first and the last time are nodes (at least two when the times
/// differ).
std::vector<double> segmentNodeTimes(const std::vector<double>& times_s,
                                     const std::vector<double>& swept_deg, double segment_deg);

/// Refines `track` with the points (see the file comment). `node_times_s` from
/// segmentNodeTimes; points at or after loop_start_s are the end window of the loop
/// closure. Fewer than two nodes or no points: δ = 0 throughout, no loop closure.
DriftRefinement refineDrift(const std::vector<DriftPoint>& points, const TranslationTrack& track,
                            const std::vector<double>& node_times_s, double loop_start_s,
                            const DriftRefinementOptions& options);

}  // namespace uavip::scan
