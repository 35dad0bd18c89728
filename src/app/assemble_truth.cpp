#include "uavip/app/assemble_truth.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "uavip/core/math.h"
#include "uavip/core/parallel.h"

namespace uavip::app {
namespace {

/// The merged cloud is scored on at most this many points (an even subsample).
constexpr std::size_t kMaxScored = 200000;

}  // namespace

sim::WorldModel worldInLogFrame(const sim::WorldModel& world, const Vec3& origin_m) {
  sim::WorldModel shifted;
  for (auto r : world.rects()) {
    r.corner -= origin_m;
    shifted.addPlane(r);
  }
  for (const auto& seg : world.segments())
    shifted.addLine(seg.name, seg.a - origin_m, seg.b - origin_m);
  for (const auto& p : world.points()) shifted.addPoint(p.name, p.p - origin_m);
  return shifted;
}

void scoreStation(StationReport& s, const scan::StationCloud& c,
                  const registration::StationResult& r, const RawLogTruth::StationTruth& truth) {
  if (truth.horizontal_poses.empty()) return;
  const auto& tp = truth.horizontal_poses;
  const Vec3 origin = tp.front().translation();
  double worst = 0.0, sum = 0.0, true_max = 0.0;
  const std::size_t n = std::min(tp.size(), c.poses.size());
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 true_d = tp[k].translation() - origin;
    const double e = (c.poses[k].translation() - true_d).norm();
    worst = std::max(worst, e);
    sum += e * e;
    true_max = std::max(true_max, true_d.norm());
  }
  if (n > 0) {
    s.drift_error_max_m = worst;
    s.drift_error_rms_m = std::sqrt(sum / static_cast<double>(n));
    s.true_drift_max_m = true_max;
  }
  s.initial_pose_error_m = (r.initial_pose.translation() - origin).norm();
  s.pose_error_m = (r.pose.translation() - origin).norm();
  s.pose_error_deg = Eigen::AngleAxisd(r.pose.linear()).angle() * kRadToDeg;
}

void scoreCloud(AssembleResult& result, const sim::WorldModel& world, int threads) {
  if (world.empty() || result.cloud.empty()) return;
  const std::size_t stride = std::max<std::size_t>(1, result.cloud.size() / kMaxScored);
  // Independent per point: in blocks on every core, summed below in order.
  std::vector<double> d((result.cloud.size() + stride - 1) / stride);
  constexpr std::size_t kBlock = 4096;
  parallelFor((d.size() + kBlock - 1) / kBlock, threads, [&](std::size_t b, std::size_t) {
    for (std::size_t j = b * kBlock; j < std::min(d.size(), (b + 1) * kBlock); ++j) {
      d[j] = world.distanceToTruth(result.cloud[j * stride]);
    }
  });
  double sum = 0.0;
  for (const double v : d) sum += v * v;
  result.rms_to_truth_m = std::sqrt(sum / static_cast<double>(d.size()));
  const auto p95 =
      d.begin() + static_cast<std::ptrdiff_t>(0.95 * static_cast<double>(d.size() - 1));
  std::nth_element(d.begin(), p95, d.end());
  result.p95_to_truth_m = *p95;
  result.scored_points = d.size();
}

}  // namespace uavip::app
