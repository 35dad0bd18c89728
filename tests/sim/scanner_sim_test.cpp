// Tests of sim/scanner_sim: ray casting against hand-worked geometry and brute force,
// eq. (1) frame conventions (core/raw_log.h), IMU error bound, motion truth, seeds.
#include "uavip/sim/scanner_sim.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>

#include "uavip/core/error.h"
#include "uavip/sim/world_model.h"

namespace uavip::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDeg = M_PI / 180.0;

Rect rect(const Vec3& corner, const Vec3& u, const Vec3& v) {
  Rect r;
  r.name = "r";
  r.corner = corner;
  r.edge_u = u;
  r.edge_v = v;
  return r;
}

/// Options for exact, hand-checkable scans: no noise, no wind or tilt, no IMU error,
/// no deskew, 2 scans per scanner at a slow yaw.
ScanSimOptions exactOptions(const Vec3& station, double start_yaw_deg = 0.0) {
  ScanSimOptions o;
  o.stations = {station};
  o.start_yaw_deg = start_yaw_deg;
  o.yaw_rate_deg_s = 30.0;
  o.turn_deg = 0.75;  // 30 deg/s x 25 ms: 2 scans
  o.scanner.range_noise_m = 0.0;
  o.wind_step_m = 0.0;
  o.tilt_step_deg = 0.0;
  o.imu_error_deg = 0.0;
  o.gps_sigma_m = 0.0;
  o.deskew = false;
  o.horizontal_time_offset_s = 0.0;  // both scanners start at yaw start_yaw_deg
  return o;
}

/// Eq. (1) and the horizontal scanner's beam (core/raw_log.h), written out here
/// independently of the simulator.
Vec3 beamPoint(bool vertical, double rho, double alpha) {
  return vertical ? Vec3(-rho * std::cos(alpha), 0.0, -rho * std::sin(alpha))
                  : Vec3(rho * std::cos(alpha), rho * std::sin(alpha), 0.0);
}

TEST(RayRect, HandWorkedCases) {
  // 2 m x 1 m rectangle in the plane z = 0, x in [0, 2], y in [0, 1].
  const Rect r = rect(Vec3::Zero(), Vec3(2, 0, 0), Vec3(0, 1, 0));
  EXPECT_NEAR(intersectRayRect(Vec3(0.5, 0.5, 3), Vec3(0, 0, -1), r), 3.0, 1e-12);
  // From below: rectangles are two-sided.
  EXPECT_NEAR(intersectRayRect(Vec3(0.5, 0.5, -1), Vec3(0, 0, 1), r), 1.0, 1e-12);
  // 45° down towards +x from (1, 0.5, 1): meets z = 0 at x = 2, the edge (closed set).
  EXPECT_NEAR(intersectRayRect(Vec3(1, 0.5, 1), Vec3(1, 0, -1).normalized(), r), std::sqrt(2.0),
              1e-12);
  // Slightly shallower: meets z = 0 at x = 1 + 1/0.9 > 2, a miss.
  EXPECT_EQ(intersectRayRect(Vec3(1, 0.5, 1), Vec3(0.9, 0, -0.9 * 0.9).normalized(), r), kInf);
  // Parallel to the plane, and pointing away from it.
  EXPECT_EQ(intersectRayRect(Vec3(0.5, 0.5, 1), Vec3(1, 0, 0), r), kInf);
  EXPECT_EQ(intersectRayRect(Vec3(0.5, 0.5, 1), Vec3(0, 0, 1), r), kInf);
  // Outside in y.
  EXPECT_EQ(intersectRayRect(Vec3(0.5, 1.2, 1), Vec3(0, 0, -1), r), kInf);
  // Tilted rectangle: the plane x + z = 2 through (1, 0, 1); a ray along −x from
  // (5, 0.5, 1) hits it at x = 1 (t = 4).
  const Rect tilted = rect(Vec3(2, 0, 0), Vec3(0, 1, 0), Vec3(-2, 0, 2));
  EXPECT_NEAR(intersectRayRect(Vec3(5, 0.5, 1), Vec3(-1, 0, 0), tilted), 4.0, 1e-12);
}

TEST(RayCaster, CapsulesAndSpheresOfThinRadius) {
  WorldModel w;
  w.addLine("pole", Vec3(0, 0, 0), Vec3(0, 0, 2));
  w.addPoint("p", Vec3(3, 5, 0));
  const RayCaster caster(w, 0.1);
  EXPECT_EQ(caster.shapeCount(), 2u);
  // Side of the cylinder: 5 − 0.1.
  EXPECT_NEAR(caster.cast(Vec3(5, 0, 1), Vec3(-1, 0, 0)), 4.9, 1e-9);
  // Above the top end, 5 cm up: the end cap sphere, x = sqrt(0.1² − 0.05²).
  EXPECT_NEAR(caster.cast(Vec3(5, 0, 2.05), Vec3(-1, 0, 0)), 5.0 - std::sqrt(0.01 - 0.0025), 1e-9);
  // Above the cap: a miss.
  EXPECT_EQ(caster.cast(Vec3(5, 0, 2.2), Vec3(-1, 0, 0)), kInf);
  // Along the axis from below: the bottom cap at z = −0.1.
  EXPECT_NEAR(caster.cast(Vec3(0, 0, -3), Vec3(0, 0, 1)), 2.9, 1e-9);
  // The point as a sphere.
  EXPECT_NEAR(caster.cast(Vec3(3, 0, 0), Vec3(0, 1, 0)), 4.9, 1e-9);
  // Radius 0: segments and points are invisible.
  const RayCaster invisible(w, 0.0);
  EXPECT_EQ(invisible.shapeCount(), 0u);
  EXPECT_EQ(invisible.cast(Vec3(5, 0, 1), Vec3(-1, 0, 0)), kInf);
  // Max range cuts hits beyond it.
  EXPECT_EQ(caster.cast(Vec3(5, 0, 1), Vec3(-1, 0, 0), 4.0), kInf);
}

TEST(RayCaster, MatchesBruteForceOverEveryRectangle) {
  WorldModel w;
  w.addBox("a", Vec3(0, 0, 0), Vec3(2, 3, 1));
  w.addBox("b", Vec3(4, -2, 0), Vec3(5, 2, 4), 30.0);
  w.addCrossedPlanes("x", Vec3(-3, 3, 2), 4, 3, 20);
  w.addTree("t", Vec3(1, -4, 0));
  w.addGrass("g", Vec3(-2, -2, 0));
  w.addPlane(rect(Vec3(-10, -10, 0), Vec3(20, 0, 0), Vec3(0, 20, 0)));
  const RayCaster caster(w, 0.0);
  ASSERT_EQ(caster.shapeCount(), w.rects().size());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 o(6 * u(rng), 6 * u(rng), 0.5 + 3 * (u(rng) + 1));
    const Vec3 d = Vec3(u(rng), u(rng), u(rng)).normalized();
    double brute = kInf;
    for (const Rect& r : w.rects()) brute = std::min(brute, intersectRayRect(o, d, r));
    const double t = caster.cast(o, d);
    if (brute == kInf) {
      EXPECT_EQ(t, kInf);
    } else {
      ++hits;
      EXPECT_NEAR(t, brute, 1e-9);
    }
  }
  EXPECT_GT(hits, 1000);
}

TEST(ScannerModel, UtmThirtyLxDefaults) {
  const ScannerModel m;
  EXPECT_EQ(m.beamCount(), 1081);
  EXPECT_NEAR(m.angleMinRad(), -135.0 * kDeg, 1e-12);
  EXPECT_NEAR(m.angleStepRad(), 0.25 * kDeg, 1e-12);
  EXPECT_NEAR(m.sweepDurationS(), 0.01875, 1e-12);
  ScanSimOptions o;
  EXPECT_EQ(o.scansPerStation(), 481);  // 12 s / 25 ms + 1
}

/// A wall at x = −5 (facing +x) and a floor at z = −2, both large.
WorldModel wallAndFloor() {
  WorldModel w;
  w.addPlane(rect(Vec3(-5, -50, -50), Vec3(0, 100, 0), Vec3(0, 0, 100)));
  w.addPlane(rect(Vec3(-50, -50, -2), Vec3(100, 0, 0), Vec3(0, 100, 0)));
  return w;
}

TEST(ScanSim, VerticalScannerFollowsEquationOne) {
  // Vertical scanner at body (−0.15, 0, 0), identity mount, UAV at the origin, yaw 0.
  const SimulatedLog s = simulateScans(wallAndFloor(), exactOptions(Vec3::Zero()));
  ASSERT_EQ(s.log.stations.size(), 1u);
  const LaserScan& v = s.log.stations[0].vertical.at(0);
  ASSERT_EQ(v.ranges_m.size(), 1081u);
  EXPECT_NEAR(v.angle_min_rad, -135.0 * kDeg, 1e-12);
  auto range = [&](double alpha_deg) {
    return v.ranges_m.at(static_cast<std::size_t>(std::lround((alpha_deg + 135.0) / 0.25)));
  };
  // α = 0: x* = −ρ, the beam goes to −x: the wall, 5 − 0.15 away.
  EXPECT_NEAR(range(0.0), 4.85, 1e-5);
  // α = 90°: z* = −ρ, straight down to the floor 2 m below.
  EXPECT_NEAR(range(90.0), 2.0, 1e-5);
  // α = 45°: down and back, the floor first: 2 / sin 45°.
  EXPECT_NEAR(range(45.0), 2.0 / std::sin(45.0 * kDeg), 1e-5);
  // α = −45°: up and back, the wall: 4.85 / cos 45°.
  EXPECT_NEAR(range(-45.0), 4.85 / std::cos(45.0 * kDeg), 1e-5);
  // α = −90°: straight up, nothing: no return.
  EXPECT_EQ(range(-90.0), 0.0f);
  // α = 135° (forward and down, last beam): floor at 2 / sin 45°.
  EXPECT_NEAR(v.ranges_m.back(), 2.0 / std::sin(45.0 * kDeg), 1e-5);
}

TEST(ScanSim, HorizontalScannerAndYaw) {
  // Horizontal scanner at body (+0.15, 0, 0): beams x* = ρ cos α, y* = ρ sin α.
  const SimulatedLog s = simulateScans(wallAndFloor(), exactOptions(Vec3::Zero()));
  const LaserScan& h = s.log.stations[0].horizontal.at(0);
  // α = 0 looks forward (+x): nothing there.
  EXPECT_EQ(h.ranges_m.at(540), 0.0f);
  // α = ±135° look back at the wall: 5.15 / cos 45°.
  EXPECT_NEAR(h.ranges_m.front(), 5.15 / std::cos(45.0 * kDeg), 1e-5);
  EXPECT_NEAR(h.ranges_m.back(), 5.15 / std::cos(45.0 * kDeg), 1e-5);

  // Yawed by +90° (CCW from above): body −x points to world −y. A wall at y = −5.
  WorldModel w;
  w.addPlane(rect(Vec3(-50, -5, -50), Vec3(100, 0, 0), Vec3(0, 0, 100)));
  const SimulatedLog y = simulateScans(w, exactOptions(Vec3::Zero(), 90.0));
  EXPECT_NEAR(y.log.stations[0].vertical[0].ranges_m.at(540), 4.85, 1e-5);
  // The horizontal scanner's α = −90° beam (body −y) now points to world +x: nothing;
  // α = +90° (body +y) points to world −x: nothing; the wall is behind it (blind spot).
  EXPECT_EQ(y.log.stations[0].horizontal[0].ranges_m.at(180), 0.0f);
  // Its α = −135° beam (body (−1, −1)/√2) points to world (1, −1)/√2: the wall,
  // from (0, 0.15, 0): (5 + 0.15) / cos 45°.
  EXPECT_NEAR(y.log.stations[0].horizontal[0].ranges_m.front(), 5.15 / std::cos(45.0 * kDeg), 1e-5);
}

TEST(ScanSim, LogFrameHasItsOriginAtStationZero) {
  // Same wall, the UAV at (10, 20, 3): ranges unchanged, truth pose at the origin.
  WorldModel w;
  w.addPlane(rect(Vec3(5, -50, -50), Vec3(0, 100, 0), Vec3(0, 0, 100)));
  ScanSimOptions o = exactOptions(Vec3(10, 20, 3));
  o.stations.push_back(Vec3(12, 21, 3));
  o.gps_sigma_m = 0.0;
  const SimulatedLog s = simulateScans(w, o);
  EXPECT_TRUE(s.origin_m.isApprox(Vec3(10, 20, 3)));
  // The wall is 5 m behind (−x); the vertical scanner sits 0.15 m back.
  EXPECT_NEAR(s.log.stations[0].vertical[0].ranges_m.at(540), 5.0 - 0.15, 1e-5);
  EXPECT_LT(s.truth.stations[0].vertical_poses[0].translation().norm(), 1e-12);
  EXPECT_TRUE(s.truth.stations[1].vertical_poses[0].translation().isApprox(Vec3(2, 1, 0)));
  EXPECT_TRUE(s.log.stations[0].recorded_position.isZero());
  EXPECT_TRUE(s.log.stations[1].recorded_position.isApprox(Vec3(2, 1, 0)));
  // Station 1 starts after station 0's turn.
  EXPECT_GT(s.log.stations[1].vertical[0].t_start_s, s.log.stations[0].vertical.back().t_start_s);
}

/// Every return, mapped to the log frame with the given body pose per beam, lies on
/// the world (shifted by the origin).
double worstDistance(const WorldModel& w, const SimulatedLog& s,
                     const std::function<Eigen::Isometry3d(int, bool, const LaserScan&, std::size_t,
                                                           std::size_t)>& pose) {
  double worst = 0.0;
  std::size_t returns = 0;
  for (std::size_t st = 0; st < s.log.stations.size(); ++st) {
    for (const bool vertical : {true, false}) {
      const auto& scans = vertical ? s.log.stations[st].vertical : s.log.stations[st].horizontal;
      const Eigen::Isometry3d& mount = vertical ? s.log.body_T_vertical : s.log.body_T_horizontal;
      for (std::size_t i = 0; i < scans.size(); ++i) {
        const LaserScan& scan = scans[i];
        for (std::size_t b = 0; b < scan.ranges_m.size(); ++b) {
          if (scan.ranges_m[b] == 0.0f) continue;
          ++returns;
          const double alpha = scan.angle_min_rad + static_cast<double>(b) * scan.angle_step_rad;
          const Vec3 x = pose(static_cast<int>(st), vertical, scan, i, b) *
                         (mount * beamPoint(vertical, scan.ranges_m[b], alpha));
          worst = std::max(worst, w.distanceToTruth(x + s.origin_m));
        }
      }
    }
  }
  EXPECT_GT(returns, 1000u);
  return worst;
}

WorldModel smallRoom() {
  WorldModel w;
  w.addBox("room_wall", Vec3(-6, -5, -1), Vec3(-5.5, 5, 4));
  w.addBox("pillar", Vec3(2, 1, -1), Vec3(3, 2, 4), 15.0);
  w.addPlane(rect(Vec3(-20, -20, -1), Vec3(40, 0, 0), Vec3(0, 40, 0)));
  w.addPlane(rect(Vec3(-20, -20, 3), Vec3(40, 0, 0), Vec3(0, 40, 0)));
  w.addTree("tree", Vec3(-2, 3, -1));
  return w;
}

TEST(ScanSim, ReturnsMappedWithTruePosesLieOnTheWorld) {
  // Wind, tilt and yaw on, no noise, no deskew: the truth pose at each scan start
  // maps every beam exactly onto the world.
  const WorldModel w = smallRoom();
  ScanSimOptions o = exactOptions(Vec3(0, 0, 0.5));
  o.turn_deg = 7.5;  // 11 scans
  o.wind_step_m = 0.01;
  o.tilt_step_deg = 0.2;
  o.vertical_mount_rpy_deg = Vec3(0, 0, 5);
  o.horizontal_mount_m = Vec3(0.1, 0.05, -0.1);
  const SimulatedLog s = simulateScans(w, o);
  double moved = 0.0;
  for (const auto& T : s.truth.stations[0].vertical_poses)
    moved = std::max(moved, T.translation().norm());
  EXPECT_GT(moved, 0.005);  // the wind did push
  const double worst =
      worstDistance(w, s, [&](int st, bool vertical, const LaserScan&, std::size_t i, std::size_t) {
        const auto& t = s.truth.stations[static_cast<std::size_t>(st)];
        return vertical ? t.vertical_poses[i] : t.horizontal_poses[i];
      });
  EXPECT_LT(worst, 1e-4);  // float ranges
}

TEST(ScanSim, DeskewCastsEachBeamFromItsOwnTime) {
  // No wind or tilt: the true pose at any t is the yaw ramp, written out here.
  const WorldModel w = smallRoom();
  ScanSimOptions o = exactOptions(Vec3(0, 0, 0.5), 10.0);
  o.turn_deg = 9.0;         // 5 scans
  o.yaw_rate_deg_s = 90.0;  // fast, so skew matters: 1.7° over a sweep
  o.deskew = true;
  const SimulatedLog s = simulateScans(w, o);
  auto yawPose = [&](double t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd((10.0 + 90.0 * t) * kDeg, Vec3::UnitZ()).toRotationMatrix();
    return T;
  };
  const double deskewed =
      worstDistance(w, s, [&](int, bool, const LaserScan& scan, std::size_t, std::size_t b) {
        return yawPose(scan.beamTime(b));
      });
  EXPECT_LT(deskewed, 1e-4);
  const double at_start =
      worstDistance(w, s, [&](int, bool, const LaserScan& scan, std::size_t, std::size_t) {
        return yawPose(scan.t_start_s);
      });
  EXPECT_GT(at_start, 0.05);  // ignoring the sweep time misplaces far beams
}

TEST(ScanSim, RangeNoiseHasTheConfiguredSigma) {
  WorldModel w;
  w.addPlane(rect(Vec3(-5, -50, -50), Vec3(0, 100, 0), Vec3(0, 0, 100)));
  ScanSimOptions noisy = exactOptions(Vec3::Zero());
  noisy.scanner.range_noise_m = 0.02;
  const SimulatedLog clean = simulateScans(w, exactOptions(Vec3::Zero()));
  const SimulatedLog s = simulateScans(w, noisy);
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  const auto& a = s.log.stations[0].vertical[0].ranges_m;
  const auto& b = clean.log.stations[0].vertical[0].ranges_m;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] == 0.0f || b[i] == 0.0f) continue;
    const double d = a[i] - b[i];
    sum += d;
    sum2 += d * d;
    ++n;
  }
  ASSERT_GT(n, 300);
  const double mean = sum / n;
  const double sigma = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(sigma, 0.02, 0.004);
  EXPECT_NEAR(mean, 0.0, 0.004);
}

TEST(ScanSim, NoReturnBeyondMaxRange) {
  WorldModel w;
  w.addPlane(rect(Vec3(-35, -50, -50), Vec3(0, 100, 0), Vec3(0, 0, 100)));  // 35 m away
  const SimulatedLog s = simulateScans(w, exactOptions(Vec3::Zero()));
  for (const float r : s.log.stations[0].vertical[0].ranges_m) EXPECT_EQ(r, 0.0f);
  EXPECT_EQ(s.returns, 0u);
  ScanSimOptions o = exactOptions(Vec3::Zero());
  o.scanner.max_range_m = 40.0;
  EXPECT_GT(simulateScans(w, o).returns, 0u);
}

TEST(ScanSim, ImuSamplesStayWithinTheirErrorOfTheTruth) {
  const WorldModel w = smallRoom();
  ScanSimOptions o;
  o.stations = {Vec3(0, 0, 0.5)};
  o.turn_deg = 45.0;         // 61 scans
  o.scanner.fov_deg = 10.0;  // few beams: only the IMU and the truth matter here
  o.imu_rate_hz = 400.0;     // every 10th sample is at a vertical scan start
  o.imu_error_deg = 0.5;
  const SimulatedLog s = simulateScans(w, o);
  const auto& st = s.log.stations[0];
  const auto& poses = s.truth.stations[0].vertical_poses;
  double worst = 0.0, sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const ImuSample& m = st.imu.at(10 * i);
    ASSERT_NEAR(m.t_s, st.vertical[i].t_start_s, 1e-9);
    const double angle = m.world_q_body.angularDistance(Eigen::Quaterniond(poses[i].linear()));
    worst = std::max(worst, angle);
    sum += angle;
    ++n;
  }
  EXPECT_LE(worst, 0.5 * kDeg + 1e-9);
  EXPECT_GT(sum / n, 0.1 * kDeg);  // the error is there
  // The IMU covers every scan: from the first scan start to past the last beam.
  EXPECT_LE(st.imu.front().t_s, st.vertical.front().t_start_s);
  EXPECT_GE(st.imu.back().t_s, st.horizontal.back().t_start_s + st.horizontal.back().duration_s);
}

TEST(ScanSim, WindStaysWithinItsBound) {
  const WorldModel w = smallRoom();
  ScanSimOptions o;
  o.stations = {Vec3(0, 0, 0.5)};
  o.turn_deg = 90.0;
  o.scanner.fov_deg = 10.0;
  o.wind_step_m = 0.05;  // large steps: the bound is reached
  o.wind_bound_m = 0.1;
  const SimulatedLog s = simulateScans(w, o);
  double reach = 0.0;
  for (const auto& T : s.truth.stations[0].horizontal_poses) {
    EXPECT_LE(T.translation().cwiseAbs().maxCoeff(), 0.1 + 1e-12);
    reach = std::max(reach, T.translation().cwiseAbs().maxCoeff());
  }
  EXPECT_GT(reach, 0.09);
}

TEST(ScanSim, SameSeedSameLogOtherSeedOtherLog) {
  const WorldModel w = smallRoom();
  ScanSimOptions o;
  o.stations = {Vec3(0, 0, 0.5), Vec3(1, 1, 0.5)};
  o.turn_deg = 6.0;
  o.scanner.fov_deg = 90.0;
  const SimulatedLog a = simulateScans(w, o);
  const SimulatedLog b = simulateScans(w, o);
  o.seed = 2;
  const SimulatedLog c = simulateScans(w, o);
  ASSERT_EQ(a.log.stations.size(), 2u);
  for (std::size_t s = 0; s < 2; ++s) {
    ASSERT_EQ(a.log.stations[s].vertical.size(), b.log.stations[s].vertical.size());
    for (std::size_t i = 0; i < a.log.stations[s].vertical.size(); ++i) {
      EXPECT_EQ(a.log.stations[s].vertical[i].ranges_m, b.log.stations[s].vertical[i].ranges_m);
      EXPECT_EQ(a.log.stations[s].horizontal[i].ranges_m, b.log.stations[s].horizontal[i].ranges_m);
    }
    EXPECT_EQ(a.log.stations[s].recorded_position, b.log.stations[s].recorded_position);
    EXPECT_TRUE(a.log.stations[s].imu.back().world_q_body.isApprox(
        b.log.stations[s].imu.back().world_q_body, 0.0));
  }
  EXPECT_NE(a.log.stations[0].vertical[0].ranges_m, c.log.stations[0].vertical[0].ranges_m);
  EXPECT_NE(a.log.stations[1].recorded_position, c.log.stations[1].recorded_position);
}

TEST(ScanSim, BadOptionsNameTheField) {
  const WorldModel w = smallRoom();
  auto expectError = [&](const ScanSimOptions& o, const std::string& field) {
    try {
      simulateScans(w, o);
      ADD_FAILURE() << "expected an error naming " << field;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  ScanSimOptions o;
  expectError(o, "stations");
  o.stations = {Vec3::Zero()};
  ScanSimOptions bad = o;
  bad.yaw_rate_deg_s = 0.0;
  expectError(bad, "yaw_rate_deg_s");
  bad = o;
  bad.scanner.range_noise_m = -0.01;
  expectError(bad, "range_noise_m");
  bad = o;
  bad.imu_rate_hz = std::nan("");
  expectError(bad, "imu_rate_hz");
  bad = o;
  bad.scanner.min_range_m = 40.0;
  expectError(bad, "min_range_m");
}

}  // namespace
}  // namespace uavip::sim
