// Stage 2 against known transforms and the scanner simulator's ground truth.

#include "uavip/registration/station_registration.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>

#include "uavip/core/error.h"
#include "uavip/core/voxel_key.h"
#include "uavip/scan/station_assembler.h"
#include "uavip/sim/scanner_sim.h"
#include "uavip/sim/surface_sampler.h"
#include "uavip/sim/world_model.h"

namespace uavip::registration {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

/// A 14 × 8 × 4 m hall with two pillars and a crate.
sim::WorldModel hall() {
  sim::WorldModel w;
  w.addBox("hall", {-4.0, -3.0, -1.5}, {10.0, 5.0, 2.5});
  w.addBox("pillar1", {2.0, 1.5, -1.5}, {2.6, 2.1, 2.5});
  w.addBox("pillar2", {6.0, -1.0, -1.5}, {6.5, -0.4, 2.5}, 15.0);
  w.addBox("crate", {-3.0, -2.5, -1.5}, {-2.0, -1.7, -0.7}, 20.0);
  return w;
}

double yawOfRotation(const Eigen::Matrix3d& r) { return std::atan2(r(1, 0), r(0, 0)); }

TEST(InitialStationPose, FromRecordedPositionsRelativeToStationZero) {
  RawLog log;
  log.stations.resize(2);
  log.stations[0].recorded_position = Vec3(1.0, 2.0, 0.5);
  log.stations[0].recorded_yaw_rad = 0.1;
  log.stations[1].recorded_position = Vec3(6.0, 3.0, 0.7);
  log.stations[1].recorded_yaw_rad = 0.4;
  const Eigen::Isometry3d p = initialStationPose(log, 1);
  EXPECT_TRUE(p.translation().isApprox(Vec3(5.0, 1.0, 0.2), 1e-12));
  EXPECT_TRUE(p.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  // With recorded yaw: (0.4 − imu 0.25) − (0.1 − imu 0.1) = 0.15 rad about z.
  const Eigen::Isometry3d q = initialStationPose(log, 1, true, 0.25, 0.1);
  EXPECT_NEAR(yawOfRotation(q.linear()), 0.15, 1e-12);
  EXPECT_THROW(initialStationPose(log, 2), InputError);
}

/// Station 1 is station 0's cloud seen from a frame moved by a known transform.
std::vector<StationInput> knownPair(const Eigen::Isometry3d& truth) {
  sim::WorldModel w = hall();
  sim::SampleOptions so;
  so.spacing_m = 0.1;
  so.noise_sigma_m = 0.005;
  const PointList cloud = sim::sampleSurfaces(w, so);
  std::vector<StationInput> in(2);
  in[0].id = 0;
  in[0].points = cloud;
  in[1].id = 1;
  const Eigen::Isometry3d inv = truth.inverse();
  for (const auto& p : cloud) in[1].points.push_back(inv * p);  // station frame of station 1
  return in;
}

class KnownTransform : public ::testing::TestWithParam<Method> {};

TEST_P(KnownTransform, RecoversAnOffsetOfThirtyCentimetresAndTwoDegrees) {
  const Eigen::Isometry3d truth =
      Eigen::Translation3d(0.3, -0.25, 0.1) * Eigen::AngleAxisd(2.0 * kDeg, Vec3::UnitZ());
  RegistrationOptions o;
  o.method = GetParam();
  const RegistrationResult r = registerStations(knownPair(truth), o);  // initial pose: identity
  ASSERT_EQ(r.stations.size(), 2u);
  EXPECT_TRUE(r.stations[1].converged);
  const Eigen::Isometry3d err = truth.inverse() * r.stations[1].pose;
  EXPECT_LT(err.translation().norm(), 0.01) << toString(GetParam());
  EXPECT_LT(Eigen::AngleAxisd(err.linear()).angle(), 0.2 * kDeg) << toString(GetParam());
  EXPECT_TRUE(r.stations[0].pose.isApprox(Eigen::Isometry3d::Identity()));
}

INSTANTIATE_TEST_SUITE_P(Methods, KnownTransform,
                         ::testing::Values(Method::IcpPointToPlane, Method::Gicp),
                         [](const auto& info) { return toString(info.param); });

TEST(RegisterStations, TranslationOnlyRecoversAPureOffset) {
  // Rotation known (IMU): the translation-only point-to-plane ICP after the coarse search.
  const Eigen::Isometry3d truth(Eigen::Translation3d(0.7, -0.45, 0.15));
  RegistrationOptions o;
  o.method = Method::PointToPlaneTranslation;
  const RegistrationResult r = registerStations(knownPair(truth), o);
  EXPECT_LT((r.stations[1].pose.translation() - truth.translation()).norm(), 0.01);
  EXPECT_TRUE(r.stations[1].pose.linear().isApprox(Eigen::Matrix3d::Identity()));
}

TEST(RegisterStations, ADirectionNoSurfaceFacesKeepsTheRecordedPositionAndIsReported) {
  // A floor and one wall facing −x: x and z are seen, y is not (sliding along the
  // wall changes nothing). The start is off by (0.25, 0.3, −0.1): x and z must be
  // recovered, y must stay where the recorded position put it (not drift), and
  // the report must name y as the weakest direction with too little information.
  sim::WorldModel w;
  w.addPlane({"floor", Vec3(-2.0, -5.0, 0.0), Vec3(12.0, 0.0, 0.0), Vec3(0.0, 10.0, 0.0)});
  w.addPlane({"wall", Vec3(8.0, -5.0, 0.0), Vec3(0.0, 10.0, 0.0), Vec3(0.0, 0.0, 3.0)});
  sim::SampleOptions so;
  so.spacing_m = 0.1;
  so.noise_sigma_m = 0.005;
  const PointList cloud = sim::sampleSurfaces(w, so);
  const Eigen::Isometry3d truth(Eigen::Translation3d(1.0, 0.5, 0.2));
  std::vector<StationInput> in(2);
  in[0].points = cloud;
  in[1].id = 1;
  for (const auto& p : cloud) in[1].points.push_back(truth.inverse() * p);
  const Vec3 start_error(0.25, 0.3, -0.1);
  in[1].initial_pose = Eigen::Translation3d(start_error) * truth;
  const RegistrationResult r = registerStations(in);
  const Vec3 err = r.stations[1].pose.translation() - truth.translation();
  EXPECT_LT(std::abs(err.x()), 0.01);
  EXPECT_LT(std::abs(err.z()), 0.01);
  EXPECT_NEAR(err.y(), start_error.y(), 0.01);
  EXPECT_LT(r.stations[1].information(0), kMinInformationPairs);
  EXPECT_GT(r.stations[1].information(1), 10.0 * kMinInformationPairs);
  EXPECT_GT(std::abs(r.stations[1].weakest_direction.y()), 0.99);
}

TEST(RegisterStations, EmptyStationsAreKeptButSkipped) {
  auto in = knownPair(Eigen::Isometry3d::Identity());
  in.insert(in.begin() + 1, StationInput{7, {}, Eigen::Isometry3d::Identity()});
  const RegistrationResult r = registerStations(in);
  ASSERT_EQ(r.stations.size(), 3u);
  EXPECT_EQ(r.stations[1].id, 7);
  EXPECT_FALSE(r.stations[1].converged);
  EXPECT_FALSE(r.merged.empty());
  std::vector<StationInput> none(2);
  EXPECT_THROW(registerStations(none), InputError);
  RegistrationOptions bad;
  bad.downsample_m = 0.0;
  EXPECT_THROW(bad.validate(), InputError);
  RegistrationOptions few;
  few.normal_k = 2;  // a normal needs 3 points
  try {
    few.validate("registration");
    ADD_FAILURE() << "no throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("registration: normal_k must be >= 3"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(methodFromString("sgd"), InputError);
}

TEST(RegisterStations, SimulatedStationsMatchTheTruth) {
  // Three stations in the hall, the simulator's default noise (σ range 2 cm, IMU
  // 0.5°, wind walk, GPS σ 0.5 m). Tolerances: station pose ≤ 3 cm, merged cloud RMS
  // to the true surfaces ≤ 3 cm, loop closure ≤ 5 cm at every station.
  const sim::WorldModel w = hall();
  sim::ScanSimOptions so;
  so.stations = {Vec3(0.0, 0.0, 0.0), Vec3(4.0, 2.5, 0.3), Vec3(8.0, -0.5, -0.2)};
  so.yaw_rate_deg_s = 90.0;
  so.seed = 11;
  const sim::SimulatedLog s = sim::simulateScans(w, so);

  std::vector<StationInput> in;
  for (std::size_t i = 0; i < s.log.stations.size(); ++i) {
    const scan::StationCloud c = scan::assembleStation(s.log, i);
    EXPECT_LT(c.loop_closure_m, 0.05) << "station " << i;
    in.push_back({c.station_id, c.points, initialStationPose(s.log, i)});
  }
  const RegistrationResult r = registerStations(in);
  ASSERT_EQ(r.stations.size(), 3u);
  double worst_initial = 0.0;
  for (std::size_t i = 0; i < 3; ++i) {
    // Station frame origin: the UAV centre at the station's first horizontal scan.
    const Vec3 truth = s.truth.stations[i].horizontal_poses.front().translation();
    worst_initial =
        std::max(worst_initial, (r.stations[i].initial_pose.translation() - truth).norm());
    EXPECT_LT((r.stations[i].pose.translation() - truth).norm(), 0.03) << "station " << i;
    EXPECT_LT(Eigen::AngleAxisd(r.stations[i].pose.linear()).angle(), 0.3 * kDeg)
        << "station " << i;
  }
  EXPECT_GT(worst_initial, 0.2);  // the recorded positions alone are far off
  double sum = 0.0;
  for (const auto& p : r.merged) sum += std::pow(w.distanceToTruth(p + s.origin_m), 2);
  EXPECT_LT(std::sqrt(sum / static_cast<double>(r.merged.size())), 0.03);

  // The merged cloud is the centroid of every occupied output voxel of the placed
  // stations (a map from voxel to sum, in point order), and the merge on both cores
  // (the default) gives the one-thread cloud bit for bit.
  const RegistrationOptions defaults;
  std::map<std::array<std::int64_t, 3>, std::pair<Vec3, int>> voxels;
  for (std::size_t i = 0; i < in.size(); ++i) {
    for (const auto& q : in[i].points) {
      const Vec3 p = r.stations[i].pose * q;
      auto& [sum_of, count] = voxels[VoxelKeyer::latticeIndex(p, defaults.output_voxel_m)];
      if (count == 0) sum_of = Vec3::Zero();
      sum_of += p;
      ++count;
    }
  }
  PointList expected;
  for (const auto& [key, v] : voxels) expected.push_back(v.first / static_cast<double>(v.second));
  PointList merged = r.merged;
  const auto lexicographic = [](const Vec3& a, const Vec3& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  };
  std::sort(expected.begin(), expected.end(), lexicographic);
  std::sort(merged.begin(), merged.end(), lexicographic);
  EXPECT_EQ(merged, expected);
  RegistrationOptions one_thread;
  one_thread.threads = 1;
  const RegistrationResult r1 = registerStations(in, one_thread);
  EXPECT_EQ(r1.merged, r.merged);
  for (std::size_t i = 0; i < in.size(); ++i) {  // the search and the ICP too
    EXPECT_EQ(r1.stations[i].pose.matrix(), r.stations[i].pose.matrix()) << "station " << i;
    EXPECT_EQ(r1.stations[i].iterations, r.stations[i].iterations);
  }
  EXPECT_GT(r.merged.size(), 2u * 65536u);  // large enough to be merged on two threads
}

}  // namespace
}  // namespace uavip::registration
