#pragma once
/// \file
/// The steps of stage 1 (paper §II-A) that the sources of src/scan share; private to
/// src/scan. One file per job: scan_icp.cpp (2D ICP of a horizontal scan, point-to-line
/// or PCL's), imu_track.cpp (R(t) from the IMU), odometry.cpp (T in xy from the
/// horizontal scans, z from the nadir and zenith beams), drift_track.cpp (T(t) refined
/// on every beam, drift_refinement.h), station_assembler.cpp (the options, eq. (1) on
/// every beam, assembleStation).

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "uavip/core/raw_log.h"
#include "uavip/core/types.h"
#include "uavip/scan/drift_refinement.h"
#include "uavip/scan/scan_grid.h"
#include "uavip/scan/station_assembler.h"

namespace uavip::scan {

using Vec2 = Eigen::Vector2d;

/// The 2D rotation by `theta` [rad].
Eigen::Matrix2d rot2(double theta);

/// cos α and sin α of every beam of a scan, α = angle_min + i·step (eq. (1)), taken
/// once per scan geometry and kept while the next scans share it (each scanner's
/// do): the same values std::cos and std::sin give for that α, so the beams are the
/// verticalBeam / horizontalBeam ones bit for bit, without two trig calls per beam.
class BeamAngles {
 public:
  /// Makes the table fit `s` (recomputed only when its geometry differs).
  void use(const LaserScan& s) {
    if (s.angle_min_rad == angle_min_ && s.angle_step_rad == angle_step_ &&
        s.ranges_m.size() <= cos_.size())
      return;
    angle_min_ = s.angle_min_rad;
    angle_step_ = s.angle_step_rad;
    cos_.resize(s.ranges_m.size());
    sin_.resize(s.ranges_m.size());
    for (std::size_t i = 0; i < cos_.size(); ++i) {
      const double a = angle_min_ + static_cast<double>(i) * angle_step_;
      cos_[i] = std::cos(a);
      sin_[i] = std::sin(a);
    }
  }
  /// verticalBeam(r, α_i).
  Vec3 vertical(double r, std::size_t i) const { return verticalBeam(r, cos_[i], sin_[i]); }
  /// horizontalBeam(r, α_i).
  Vec3 horizontal(double r, std::size_t i) const { return horizontalBeam(r, cos_[i], sin_[i]); }

 private:
  double angle_min_{std::numeric_limits<double>::quiet_NaN()};  // no table yet
  double angle_step_{std::numeric_limits<double>::quiet_NaN()};
  std::vector<double> cos_, sin_;
};

/// A horizontal scan as 2D points (in beam order) in some frame, with the line
/// normals there (zero where the neighbourhood is not a line).
struct Scan2D {
  std::vector<Vec2> pts;
  std::vector<Vec2> normals;
};

/// A keyframe: points in the station frame with line normals (zero where unknown).
struct Reference {
  std::vector<Vec2> pts;
  std::vector<Vec2> normals;
};

/// A scan placed by (theta, t), with the line normal of each point (AssemblerTuning's
/// line fit; zero where the neighbourhood is not a line).
Reference makeReference(const Scan2D& scan, double theta, const Vec2& t,
                        const AssemblerTuning& tuning);

/// What one 2D ICP run found.
struct IcpResult {
  double theta{0.0};
  Vec2 t{Vec2::Zero()};
  int iterations{0};
  double rms{0.0};
  std::size_t pairs{0};
  /// Smallest eigenvalue of the pairs' Σ w·n nᵀ (translation block) in the last
  /// iteration: how many effective pairs fix the least constrained direction.
  double min_information{0.0};
  bool converged{true};  ///< false when the solver says it did not converge (PCL)
};

/// Point-to-line ICP: finds (theta, t) with rot(theta)·src + t ≈ reference, starting
/// from the given guess. Huber-weighted Gauss–Newton, correspondences re-found each step.
IcpResult icpPointToLine(const Scan2D& src, const Reference& ref, const ScanGrid& grid,
                         double theta0, const Vec2& t0, const AssemblerOptions& o, int stride);

/// The same problem with pcl::IterativeClosestPoint (point-to-point, 2D estimate).
IcpResult icpPcl(const Scan2D& src, const Reference& ref, double theta0, const Vec2& t0,
                 const AssemblerOptions& o, int stride);

/// Vertical drift z per vertical scan from the nadir/zenith beams (0 without
/// estimate_z): each scan's height offset against height maps of the ground below
/// and the ceiling above built from the scans before it. `xy` places the beams.
std::vector<double> verticalDrift(const RawLog& log, const Station& st, const ImuTrack& imu,
                                  const TranslationTrack& xy, const AssemblerOptions& options);

/// T(t) from the odometry (xy at the horizontal scans' mid times) and the vertical
/// drift (z of the vertical scan nearest in time). Without horizontal scans: the
/// vertical scans' start times, z only.
TranslationTrack odometryTrack(const Station& st, const StationOdometry& odo,
                               const std::vector<double>& z_of_vscan);

/// The joint refinement of T(t) (drift_refinement.h) on `track`, in place; returns it.
DriftRefinement refineTrack(const RawLog& log, const Station& st, const ImuTrack& imu,
                            const AssemblerOptions& options, TranslationTrack& track);

}  // namespace uavip::scan
