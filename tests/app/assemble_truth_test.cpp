// Stages 1-2 scored against the truth (app/assemble_truth.h): hand-computed drift,
// pose and cloud errors on small known inputs.
#include "uavip/app/assemble_truth.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

namespace uavip::app {
namespace {

Eigen::Isometry3d at(const Vec3& t) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = t;
  return pose;
}

TEST(AssembleTruth, WorldInLogFrameIsTheWorldShifted) {
  sim::WorldModel world;
  world.addPlane({"floor", Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 0)});
  world.addLine("pole", Vec3(20, 0, 0), Vec3(20, 0, 5));
  world.addPoint("tip", Vec3(-5, 3, 2));
  const Vec3 origin(100.0, -40.0, 3.0);
  const sim::WorldModel shifted = worldInLogFrame(world, origin);
  for (const Vec3& p : {Vec3(5, 5, 2), Vec3(21, 1, 3), Vec3(-5, 3, 2.5), Vec3(30, -7, -4)}) {
    EXPECT_NEAR(shifted.distanceToTruth(p - origin), world.distanceToTruth(p), 1e-9);
  }
  EXPECT_TRUE(worldInLogFrame(sim::WorldModel{}, origin).empty());
}

TEST(AssembleTruth, StationErrorsAgainstTheTruePoses) {
  RawLogTruth::StationTruth truth;  // the UAV drifts 0.1 m, then 0.3 m along x
  truth.horizontal_poses = {at(Vec3(10.0, 0, 0)), at(Vec3(10.1, 0, 0)), at(Vec3(10.3, 0, 0))};
  scan::StationCloud c;  // estimated displacements: 0, 0.1, 0.2 (and one pose too many)
  c.poses = {at(Vec3::Zero()), at(Vec3(0.1, 0, 0)), at(Vec3(0.2, 0, 0)), at(Vec3(9, 9, 9))};
  registration::StationResult r;
  r.initial_pose = at(Vec3(10.0, 0.2, 0.0));
  r.pose = at(Vec3(10.0, 0.0, 0.05));
  r.pose.linear() = Eigen::AngleAxisd(5.0 * M_PI / 180.0, Vec3::UnitZ()).toRotationMatrix();
  StationReport s;
  scoreStation(s, c, r, truth);
  ASSERT_TRUE(s.drift_error_max_m && s.drift_error_rms_m && s.true_drift_max_m);
  EXPECT_NEAR(*s.drift_error_max_m, 0.1, 1e-12);
  EXPECT_NEAR(*s.drift_error_rms_m, std::sqrt(0.01 / 3.0), 1e-12);
  EXPECT_NEAR(*s.true_drift_max_m, 0.3, 1e-12);
  EXPECT_NEAR(s.initial_pose_error_m.value(), 0.2, 1e-12);
  EXPECT_NEAR(s.pose_error_m.value(), 0.05, 1e-12);
  EXPECT_NEAR(s.pose_error_deg.value(), 5.0, 1e-9);

  StationReport none;  // no true pose: nothing scored
  scoreStation(none, c, r, RawLogTruth::StationTruth{});
  EXPECT_FALSE(none.drift_error_max_m || none.pose_error_m || none.pose_error_deg);
}

TEST(AssembleTruth, CloudErrorsAgainstTheTrueSurface) {
  sim::WorldModel world;
  world.addPlane({"floor", Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 0)});
  AssembleResult result;  // 21 points 0, 0.01, …, 0.20 m above the floor
  double sum = 0.0;
  for (int i = 0; i <= 20; ++i) {
    result.cloud.emplace_back(1.0 + 0.1 * i, 2.0, 0.01 * i);
    sum += 0.0001 * i * i;
  }
  scoreCloud(result, world, 2);
  EXPECT_EQ(result.scored_points, 21u);
  EXPECT_NEAR(result.rms_to_truth_m.value(), std::sqrt(sum / 21.0), 1e-12);
  EXPECT_NEAR(result.p95_to_truth_m.value(), 0.19, 1e-12);  // element ⌊0.95 · 20⌋ of 21

  AssembleResult empty;
  scoreCloud(empty, world, 2);
  EXPECT_FALSE(empty.rms_to_truth_m.has_value());
  EXPECT_EQ(empty.scored_points, 0u);
}

}  // namespace
}  // namespace uavip::app
