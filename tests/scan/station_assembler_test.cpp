// Stage 1 against hand-worked beams and against the ground truth of the scanner
// simulator (sim::simulateScans: exact ray casting of a small room).

#include "uavip/scan/station_assembler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "uavip/core/error.h"
#include "uavip/scan/drift_refinement.h"
#include "uavip/sim/scanner_sim.h"
#include "uavip/sim/world_model.h"

namespace uavip::scan {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

/// A 9 × 7 × 4 m room with a pillar and a crate, the UAV near its centre.
sim::WorldModel room() {
  sim::WorldModel w;
  w.addBox("room", {-4.0, -3.0, -1.5}, {5.0, 4.0, 2.5});
  w.addBox("pillar", {2.0, 1.5, -1.5}, {2.6, 2.1, 2.5});
  w.addBox("crate", {-3.0, -2.5, -1.5}, {-2.0, -1.7, -0.7}, 20.0);
  return w;
}

sim::ScanSimOptions quiet() {
  sim::ScanSimOptions o;
  o.stations = {Vec3(0.3, 0.2, 0.0)};
  o.start_yaw_deg = 30.0;
  o.yaw_rate_deg_s = 90.0;  // 4 s per turn, 161 scans per scanner: small and fast
  o.scanner.range_noise_m = 0.0;
  o.imu_error_deg = 0.0;
  o.wind_step_m = 0.0;
  o.tilt_step_deg = 0.0;
  o.gps_sigma_m = 0.0;
  o.seed = 3;
  return o;
}

/// Default noise (σ range 2 cm, IMU 0.5°), a stronger wind and tilt walk.
sim::ScanSimOptions windy() {
  sim::ScanSimOptions o = quiet();
  o.scanner.range_noise_m = 0.02;
  o.imu_error_deg = 0.5;
  o.wind_step_m = 0.01;
  o.tilt_step_deg = 0.1;
  o.tilt_bound_deg = 2.0;
  return o;
}

const sim::SimulatedLog& windyLog() {
  static const sim::SimulatedLog log = sim::simulateScans(room(), windy());
  return log;
}

double distanceToRoom(const sim::WorldModel& w, const sim::SimulatedLog& s, const Vec3& p) {
  return w.distanceToTruth(p + s.origin_m);
}

/// Trajectory error of the estimate against the truth [m]: max over horizontal scans of
/// |estimated − (true − true at the first scan)|, horizontally (xy) and vertically (z).
struct TrajError {
  double xy{0.0};
  double z{0.0};
};
TrajError trajectoryError(const StationCloud& c, const RawLogTruth::StationTruth& t) {
  TrajError e;
  const Vec3 origin = t.horizontal_poses.front().translation();
  for (std::size_t k = 0; k < c.poses.size(); ++k) {
    const Vec3 d = c.poses[k].translation() - (t.horizontal_poses[k].translation() - origin);
    e.xy = std::max(e.xy, d.head<2>().norm());
    e.z = std::max(e.z, std::abs(d.z()));
  }
  return e;
}

TEST(Eq1, VerticalBeamHandWorked) {
  // ρ = 2 m, α = 30°: x* = −2·cos 30° = −1.7320508, y* = 0, z* = −2·sin 30° = −1.
  const Vec3 x = verticalBeam(2.0, 30.0 * kDeg);
  EXPECT_NEAR(x.x(), -1.7320508, 1e-7);
  EXPECT_DOUBLE_EQ(x.y(), 0.0);
  EXPECT_NEAR(x.z(), -1.0, 1e-12);
  // α = 90°: straight down the scanner's −z; α = 0: along −x.
  EXPECT_TRUE(verticalBeam(3.0, 90.0 * kDeg).isApprox(Vec3(0.0, 0.0, -3.0), 1e-12));
  EXPECT_TRUE(verticalBeam(3.0, 0.0).isApprox(Vec3(-3.0, 0.0, 0.0), 1e-12));
}

TEST(Eq1, MountAndBodyTransformHandWorked) {
  // Mount: scanner turned 180° about body z, 0.12 m forward, 0.05 m up.
  const Eigen::Isometry3d mount =
      Eigen::Translation3d(0.12, 0.0, 0.05) * Eigen::AngleAxisd(kPi, Vec3::UnitZ());
  // Body: at (1, 2, 3), yawed 90°.
  const Eigen::Isometry3d body =
      Eigen::Translation3d(1.0, 2.0, 3.0) * Eigen::AngleAxisd(kPi / 2.0, Vec3::UnitZ());
  // x* = (−1.7320508, 0, −1) → Rz(180°): (1.7320508, 0, −1) → + mount: (1.8520508, 0, −0.95)
  // → Rz(90°): (0, 1.8520508, −0.95) → + body: (1, 3.8520508, 2.05).
  const Vec3 x = verticalBeamToFrame(2.0, 30.0 * kDeg, mount, body);
  EXPECT_NEAR(x.x(), 1.0, 1e-9);
  EXPECT_NEAR(x.y(), 3.8520508, 1e-7);
  EXPECT_NEAR(x.z(), 2.05, 1e-9);
}

TEST(Eq1, HorizontalBeamHandWorked) {
  const Vec3 x = horizontalBeam(2.0, 30.0 * kDeg);
  EXPECT_NEAR(x.x(), 1.7320508, 1e-7);
  EXPECT_NEAR(x.y(), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(x.z(), 0.0);
}

TEST(ValidRange, RejectsZeroNanShortAndLong) {
  EXPECT_TRUE(validRange(5.0f, 0.1, 30.0));
  EXPECT_TRUE(validRange(30.0f, 0.1, 30.0));
  EXPECT_FALSE(validRange(0.0f, 0.1, 30.0));
  EXPECT_FALSE(validRange(0.05f, 0.1, 30.0));
  EXPECT_FALSE(validRange(30.5f, 0.1, 30.0));
  EXPECT_FALSE(validRange(std::numeric_limits<float>::quiet_NaN(), 0.1, 30.0));
  EXPECT_FALSE(validRange(std::numeric_limits<float>::infinity(), 0.1, 30.0));
  EXPECT_FALSE(validRange(-1.0f, 0.1, 30.0));
}

std::vector<ImuSample> yawSamples(double rate_rad_s, double dt, int n) {
  std::vector<ImuSample> s;
  for (int i = 0; i < n; ++i) {
    ImuSample x;
    x.t_s = i * dt;
    x.world_q_body = Eigen::AngleAxisd(rate_rad_s * x.t_s, Vec3::UnitZ());
    s.push_back(x);
  }
  return s;
}

TEST(ImuTrack, SlerpsBetweenSamplesAndClamps) {
  const ImuTrack track(yawSamples(kPi / 2.0, 1.0, 2), 2.0, 0.0, "test");  // 0° at t=0, 90° at t=1
  EXPECT_NEAR(yawOf(track.at(0.5)), 45.0 * kDeg, 1e-12);
  EXPECT_NEAR(yawOf(track.at(0.25)), 22.5 * kDeg, 1e-12);
  EXPECT_NEAR(yawOf(track.at(-1.0)), 0.0, 1e-12);
  EXPECT_NEAR(yawOf(track.at(7.0)), 90.0 * kDeg, 1e-12);
}

TEST(ImuTrack, SmoothingKeepsAConstantRateTurn) {
  // A local-linear fit reproduces a noise-free constant-rate turn exactly.
  const ImuTrack raw(yawSamples(0.6, 0.0025, 400), 0.01, 0.0, "test");
  const ImuTrack smooth(yawSamples(0.6, 0.0025, 400), 0.01, 0.05, "test");
  for (double t = 0.0; t < 0.99; t += 0.0173) {
    EXPECT_NEAR(yawOf(smooth.at(t)), yawOf(raw.at(t)), 1e-9) << t;
  }
}

TEST(ImuTrack, RejectsBackwardsTimeGapsAndEmpty) {
  auto s = yawSamples(0.5, 0.01, 10);
  std::swap(s[4].t_s, s[5].t_s);
  EXPECT_THROW(ImuTrack(s, 0.025, 0.0, "test"), InputError);
  auto g = yawSamples(0.5, 0.01, 10);
  for (std::size_t i = 5; i < g.size(); ++i) g[i].t_s += 0.1;  // a 0.11 s gap
  try {
    ImuTrack(g, 0.025, 0.0, "station 2");
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("station 2: IMU gap"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ImuTrack({}, 0.025, 0.0, "test"), InputError);
}

TEST(AssembleStation, NoiseFreeCloudLiesOnTheTrueSurfaces) {
  // Exact ranges, exact IMU, no wind: every point must be on a wall (eq. (1), the
  // mount, IMU slerp and per-beam deskewing at 90°/s; an undeskewed beam would be
  // off by up to 1.7° × range ≈ 15 cm).
  const sim::WorldModel w = room();
  const sim::SimulatedLog s = sim::simulateScans(w, quiet());
  const StationCloud c = assembleStation(s.log, 0);
  ASSERT_GT(c.points.size(), 100000u);
  double worst = 0.0;
  for (const auto& p : c.points) worst = std::max(worst, distanceToRoom(w, s, p));
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT(c.loop_closure_m, 1e-3);
  const TrajError e = trajectoryError(c, s.truth.stations.front());
  EXPECT_LT(e.xy, 1e-3);
  EXPECT_LT(e.z, 1e-3);
  EXPECT_EQ(c.stats.beams, c.points.size() + c.stats.invalid_beams);
}

TEST(AssembleStation, RecoversWindDriftWithinTolerance) {
  // Wind walk of 1 cm/scan (up to ±20 cm), tilt walk, σ = 2 cm ranges, 0.5° IMU error.
  // Tolerance: 3 cm horizontally, 3 cm vertically, at every horizontal scan.
  const sim::SimulatedLog& s = windyLog();
  const RawLogTruth::StationTruth& truth = s.truth.stations.front();
  // The truth really drifts: more than 5 cm somewhere, so ignoring it would fail.
  double true_drift = 0.0;
  for (const auto& p : truth.horizontal_poses) {
    true_drift = std::max(true_drift,
                          (p.translation() - truth.horizontal_poses.front().translation()).norm());
  }
  ASSERT_GT(true_drift, 0.05);
  const StationCloud c = assembleStation(s.log, 0);
  const TrajError e = trajectoryError(c, truth);
  EXPECT_LT(e.xy, 0.03);
  EXPECT_LT(e.z, 0.03);
}

TEST(AssembleStation, LoopClosureAndCloudAccuracyWithDefaultNoise) {
  const sim::WorldModel w = room();
  const sim::SimulatedLog& s = windyLog();
  const StationCloud c = assembleStation(s.log, 0);
  EXPECT_GE(c.loop_closure_m, 0.0);
  EXPECT_LT(c.loop_closure_m, 0.05);  // paper: 10 cm
  double sum = 0.0;
  for (const auto& p : c.points) sum += std::pow(distanceToRoom(w, s, p), 2);
  const double rms = std::sqrt(sum / static_cast<double>(c.points.size()));
  EXPECT_LT(rms, 0.03);
}

TEST(AssembleStation, LoopClosureIsNotReportedWhenOneWallIsAllTheScannerSees) {
  // A floor and one long wall: the horizontal scanner sees a single line and the
  // vertical one that line and the floor, so the offset along the wall between the
  // end and the start of the sweep is not measurable, in 2D or in 3D. A figure of 0
  // would claim a perfect closure; the station reports −1 instead. The room (several
  // walls) gives a figure (the test above).
  sim::WorldModel w;
  w.addPlane({"floor", Vec3(-20.0, -20.0, -1.5), Vec3(40.0, 0.0, 0.0), Vec3(0.0, 40.0, 0.0)});
  w.addPlane({"wall", Vec3(3.0, -20.0, -1.5), Vec3(0.0, 40.0, 0.0), Vec3(0.0, 0.0, 4.0)});
  const sim::SimulatedLog s = sim::simulateScans(w, windy());
  const StationCloud one_wall = assembleStation(s.log, 0);
  EXPECT_LT(one_wall.loop_closure_m, 0.0);
  EXPECT_LT(one_wall.loop_closure_information, 10.0);
  const StationCloud room_station = assembleStation(windyLog().log, 0);
  EXPECT_GT(room_station.loop_closure_information, 10.0);
  // Along the wall the refinement corrects nothing (the odometry's y is kept, up to
  // its smoothing); across it, it may.
  AssemblerOptions odometry_only;
  odometry_only.refine_drift = false;
  const StationCloud odo = assembleStation(s.log, 0, odometry_only);
  ASSERT_EQ(odo.poses.size(), one_wall.poses.size());
  for (std::size_t k = 0; k < odo.poses.size(); ++k) {
    EXPECT_NEAR(one_wall.poses[k].translation().y(), odo.poses[k].translation().y(), 0.01)
        << "scan " << k;
  }
}

/// Part of the bridge of scenarios/bridge.yaml: the deck underside, a pier of two
/// columns, the abutment and the ground (no clutter).
sim::WorldModel bridgeWithoutClutter() {
  sim::WorldModel w;
  w.addPlane({"deck", Vec3(0.0, 0.0, 3.6), Vec3(0.0, 10.0, 0.0), Vec3(22.0, 0.0, 0.0)});
  w.addBox("column_south", {10.0, 1.5, 0.0}, {12.0, 3.5, 3.6});
  w.addBox("column_north", {10.0, 6.5, 0.0}, {12.0, 8.5, 3.6});
  w.addBox("abutment", {-1.0, -0.5, 0.0}, {0.0, 10.5, 3.6});
  w.addPlane({"ground", Vec3(-6.0, -7.0, 0.0), Vec3(34.0, 0.0, 0.0), Vec3(0.0, 24.0, 0.0)});
  return w;
}

TEST(AssembleStation, VerticalScansFixTheDriftTheHorizontalScannerCannotSee) {
  // Station 1 of the bridge, under the deck east of the pier, with the bridge's
  // sensing (30°/s, σ range 1 cm, IMU 0.5°, wind walk 3 mm per scan). At 1.5 m the
  // horizontal scanner sees the columns' x faces and little else: its first scan,
  // whose blind sector faces the pier, sees nothing, so every ICP fails and the
  // odometry stays at 0, and no loop closure is measurable in its plane. The
  // vertical scanner sees the deck underside, the ground, the abutment and the
  // columns' faces all round: with the refinement the drift is found in every
  // direction. Tolerances: 5 cm horizontally (on a true drift of 10–13 cm), 3 cm
  // vertically; loop closure ≤ 5 cm (paper: 10 cm).
  sim::ScanSimOptions o;
  o.stations = {Vec3(17.0, 5.0, 1.5)};
  o.scanner.range_noise_m = 0.01;
  o.gps_sigma_m = 0.0;
  o.seed = 3;
  const sim::SimulatedLog s = sim::simulateScans(bridgeWithoutClutter(), o);
  const RawLogTruth::StationTruth& truth = s.truth.stations.front();
  double true_x = 0.0, true_y = 0.0;
  for (const auto& p : truth.horizontal_poses) {
    const Vec3 d = p.translation() - truth.horizontal_poses.front().translation();
    true_x = std::max(true_x, std::abs(d.x()));
    true_y = std::max(true_y, std::abs(d.y()));
  }
  ASSERT_GT(true_x, 0.08);
  ASSERT_GT(true_y, 0.08);

  AssemblerOptions odometry_only;
  odometry_only.refine_drift = false;
  const StationCloud odo = assembleStation(s.log, 0, odometry_only);
  EXPECT_LT(odo.loop_closure_m, 0.0);               // the premise: not measurable in 2D
  EXPECT_GT(trajectoryError(odo, truth).xy, 0.08);  // and the drift not seen

  const StationCloud c = assembleStation(s.log, 0);
  const TrajError e = trajectoryError(c, truth);
  EXPECT_LT(e.xy, 0.05);
  EXPECT_LT(e.z, 0.03);
  EXPECT_GE(c.loop_closure_information, 10.0);
  EXPECT_GE(c.loop_closure_m, 0.0);
  EXPECT_LT(c.loop_closure_m, 0.05);
  EXPECT_GT(c.stats.drift_segments, 20u);
}

TEST(AssembleStation, ImuPriorNeedsFewerIcpIterations) {
  // The paper's customisation: with the scans rotated by the IMU first, ICP has only
  // the wind translation left to find and converges in fewer iterations than plain
  // ICP, which must find the 2.25° of yaw between scans itself (same accuracy bound).
  const sim::SimulatedLog& s = windyLog();
  AssemblerOptions plain;
  plain.use_imu_prior = false;
  const StationCloud with = assembleStation(s.log, 0);
  const StationCloud without = assembleStation(s.log, 0, plain);
  EXPECT_LT(with.stats.mean_icp_iterations, without.stats.mean_icp_iterations);
  EXPECT_LT(trajectoryError(with, s.truth.stations.front()).xy, 0.03);
}

// With `icp: pcl`, a scan PCL could not align (here: no correspondence within a
// micrometre) is a failed ICP, kept at its guess, not a silent success.
TEST(AssembleStation, PclIcpThatDoesNotConvergeIsCountedAsFailed) {
  const sim::SimulatedLog& s = windyLog();
  AssemblerOptions o;
  o.icp = IcpMethod::PclPointToPoint;
  const StationCloud good = assembleStation(s.log, 0, o);
  EXPECT_EQ(good.stats.failed_icp, 0u);
  o.max_correspondence_m = 1e-6;
  const StationCloud none = assembleStation(s.log, 0, o);
  EXPECT_GT(none.stats.failed_icp, 0u);
}

// The tuning reaches the point-to-line ICP: asking for more pairs than a scan has
// beams fails every scan after the first (each keeps its guess).
TEST(AssembleStation, TuningMinPairsDecidesWhatAFailedIcpIs) {
  const sim::SimulatedLog& s = windyLog();
  EXPECT_EQ(assembleStation(s.log, 0).stats.failed_icp, 0u);
  AssemblerOptions o;
  o.tuning.min_pairs = 100000;
  const StationCloud c = assembleStation(s.log, 0, o);
  EXPECT_EQ(c.stats.failed_icp, c.stats.horizontal_scans - 1);
}

TEST(AssembleStation, SkipsInvalidRanges) {
  const sim::WorldModel w = room();
  sim::SimulatedLog s = sim::simulateScans(w, quiet());
  const StationCloud before = assembleStation(s.log, 0);
  // Corrupt valid beams of the vertical scans: 0, NaN, beyond max range, below min range, inf.
  const float bad[] = {0.0f, std::numeric_limits<float>::quiet_NaN(), 31.0f, 0.05f,
                       std::numeric_limits<float>::infinity()};
  std::size_t corrupted = 0;
  auto& scans = s.log.stations[0].vertical;
  for (std::size_t k = 0; k < scans.size(); k += 7) {
    for (std::size_t i = 100; i < scans[k].ranges_m.size(); i += 97) {
      if (scans[k].ranges_m[i] <= 0.0f) continue;
      scans[k].ranges_m[i] = bad[corrupted % 5];
      ++corrupted;
    }
  }
  ASSERT_GT(corrupted, 100u);
  const StationCloud after = assembleStation(s.log, 0);
  EXPECT_EQ(after.stats.invalid_beams, before.stats.invalid_beams + corrupted);
  EXPECT_EQ(after.points.size(), before.points.size() - corrupted);
  for (const auto& p : after.points) ASSERT_TRUE(p.allFinite());
}

TEST(AssembleStation, BadRawDataIsAnInputErrorNamingTheStation) {
  const sim::SimulatedLog s = sim::simulateScans(room(), quiet());
  {
    RawLog log = s.log;
    log.stations[0].imu.clear();
    EXPECT_THROW(assembleStation(log, 0), InputError);
  }
  {
    RawLog log = s.log;  // an IMU gap of 0.2 s (longer than a scan)
    auto& imu = log.stations[0].imu;
    const double t_cut = imu[imu.size() / 2].t_s;
    imu.erase(
        std::remove_if(imu.begin(), imu.end(),
                       [&](const ImuSample& x) { return x.t_s > t_cut && x.t_s < t_cut + 0.2; }),
        imu.end());
    try {
      assembleStation(log, 0);
      FAIL() << "no throw";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("station 0"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("gap"), std::string::npos) << e.what();
    }
  }
  {
    RawLog log = s.log;  // scan timestamps going backwards
    std::swap(log.stations[0].horizontal[10].t_start_s, log.stations[0].horizontal[11].t_start_s);
    EXPECT_THROW(assembleStation(log, 0), InputError);
  }
  {
    RawLog log = s.log;  // a station with no scans: an empty cloud, not an error
    log.stations[0].vertical.clear();
    log.stations[0].horizontal.clear();
    const StationCloud c = assembleStation(log, 0);
    EXPECT_TRUE(c.points.empty());
    EXPECT_LT(c.loop_closure_m, 0.0);
  }
  EXPECT_THROW(assembleStation(s.log, 5), InputError);
}

TEST(DriftRefinement, NodesAtEqualSharesOfTheSweptYaw) {
  // 0.5 s per sample, yaw −170°, 170°, 150° …: wrapping counts 20° per step, either way.
  const std::vector<double> t{0.0, 0.5, 1.0, 1.5, 2.0};
  const std::vector<double> yaw{-170.0 * kDeg, 170.0 * kDeg, 150.0 * kDeg, 130.0 * kDeg,
                                110.0 * kDeg};
  const std::vector<double> swept = sweptYawDeg(yaw);
  ASSERT_EQ(swept.size(), 5u);
  EXPECT_NEAR(swept.back(), 80.0, 1e-9);
  EXPECT_NEAR(timeAtSweptDeg(t, swept, 30.0), 0.75, 1e-9);
  EXPECT_DOUBLE_EQ(timeAtSweptDeg(t, swept, -5.0), 0.0);
  EXPECT_DOUBLE_EQ(timeAtSweptDeg(t, swept, 500.0), 2.0);
  // 80° in segments of about 25°: 3 segments of 26.7°.
  const std::vector<double> nodes = segmentNodeTimes(t, swept, 25.0);
  ASSERT_EQ(nodes.size(), 4u);
  EXPECT_DOUBLE_EQ(nodes.front(), 0.0);
  EXPECT_NEAR(nodes[1], 2.0 / 3.0, 1e-9);
  EXPECT_NEAR(nodes[2], 4.0 / 3.0, 1e-9);
  EXPECT_DOUBLE_EQ(nodes.back(), 2.0);
  // No points: no correction and no loop closure.
  TranslationTrack track{t, std::vector<Vec3>(5, Vec3(0.1, 0.0, 0.0))};
  EXPECT_TRUE(track.at(1.3).isApprox(Vec3(0.1, 0.0, 0.0)));
  const DriftRefinement r = refineDrift({}, track, nodes, 1.5, DriftRefinementOptions{});
  EXPECT_TRUE(r.at(1.0).isZero());
  EXPECT_LT(r.loop_closure_m, 0.0);
}

TEST(AssemblerOptions, ValidateNamesTheField) {
  AssemblerOptions o;
  o.max_correspondence_m = -1.0;
  try {
    o.validate("scan");
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_correspondence_m"), std::string::npos);
  }
  AssemblerOptions segment;
  segment.drift_segment_deg = 0.0;
  EXPECT_THROW(segment.validate(), InputError);
  AssemblerOptions iterations;
  iterations.drift_iterations = 0;
  EXPECT_THROW(iterations.validate(), InputError);
  AssemblerOptions voxel;
  voxel.drift_voxel_m = -0.5;
  EXPECT_THROW(voxel.validate(), InputError);
  AssemblerOptions tuning;
  tuning.tuning.normal_cos = 1.5;
  try {
    tuning.validate("scan");
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scan.tuning: normal_cos"), std::string::npos) << e.what();
  }
  EXPECT_EQ(icpMethodFromString("pcl"), IcpMethod::PclPointToPoint);
  EXPECT_THROW(icpMethodFromString("foo"), InputError);
}

}  // namespace
}  // namespace uavip::scan
