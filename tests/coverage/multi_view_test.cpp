// Tests of the multi-view counts (coverage/multi_view.h) against a brute-force count
// written out here: every (view, point) pair tested with the footprint frustum, the
// range, the incidence and a blocker of its own, and the rays' angles compared pair
// by pair; and a reconstruction plan checked by the same count.
#include "uavip/coverage/multi_view.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "uavip/coverage/flight_strategy.h"

namespace uavip::coverage {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// Blocks every segment that crosses the square |y| <= 0.15, |z - 0.5| <= 0.15 of the
/// plane x = 1.0 (a post between some cameras and the wall).
class PostBlocker final : public LineOfSight {
 public:
  bool clear(const Vec3& from, const Vec3& to) const override {
    const double dx = to.x() - from.x();
    if (std::abs(dx) < 1e-12) return true;
    const double t = (1.0 - from.x()) / dx;
    if (t <= 0.0 || t >= 1.0) return true;
    const Vec3 q = from + t * (to - from);
    return !(std::abs(q.y()) <= 0.15 && std::abs(q.z() - 0.5) <= 0.15);
  }
};

/// A 2 m x 1 m wall in the plane x = 0 facing +x: y in [-1, 1], z in [0, 1], sampled
/// every 5 cm at cell centres.
PointList wallSamples(double w = 2.0, double h = 1.0, double step = 0.05) {
  PointList pts;
  for (double y = -0.5 * w + 0.5 * step; y < 0.5 * w; y += step)
    for (double z = 0.5 * step; z < h; z += step) pts.emplace_back(0.0, y, z);
  return pts;
}

/// The brute-force test of one pair: the footprint frustum of a camera whose photo is
/// fw x fh at distance d (forward, right and up from yaw and pitch, no roll), range
/// <= d * slack, incidence to the normal +x <= max_incidence_deg, line of sight.
bool sees(const ViewPose& v, const Vec3& p, double fw, double fh, double d, double slack,
          double max_incidence_deg, const LineOfSight& los) {
  const double y = v.yaw_deg * kDeg, t = v.pitch_deg * kDeg;
  const Vec3 f(std::cos(t) * std::cos(y), std::cos(t) * std::sin(y), std::sin(t));
  const Vec3 r(std::sin(y), -std::cos(y), 0.0);
  const Vec3 u = r.cross(f);
  const Vec3 q = p - v.position;
  const double z = q.dot(f);
  if (z <= 0.0) return false;
  if (std::abs(q.dot(r)) > z * fw / (2.0 * d) || std::abs(q.dot(u)) > z * fh / (2.0 * d))
    return false;
  if (q.norm() > d * slack) return false;
  const Vec3 to_cam = -q.normalized();
  if (std::acos(std::clamp(to_cam.x(), -1.0, 1.0)) > max_incidence_deg * kDeg) return false;
  return los.clear(v.position, p);
}

TEST(MultiView, MatchesBruteForceCount) {
  const PointList pts = wallSamples();
  // Six cameras 1.5 m off the wall looking at it (yaw 180 = -x), two turned, one
  // behind the post, one too far, one looking away.
  const std::vector<ViewPose> views = {
      {Vec3(1.5, -0.4, 0.5), 180.0, 0.0},  {Vec3(1.5, 0.3, 0.5), 180.0, 0.0},
      {Vec3(1.4, 0.0, 0.6), 170.0, -8.0},  {Vec3(1.3, 0.8, 0.4), 195.0, 5.0},
      {Vec3(3.0, 0.0, 0.5), 180.0, 0.0},   {Vec3(1.5, 0.0, 0.5), 0.0, 0.0},
      {Vec3(1.2, -0.9, 0.9), 160.0, -20.0}};
  FootprintCameraOptions co;  // 1.2 x 0.8 m at 1.5 m, range 1.5 x 1.5 m
  co.camera.footprint_w_m = 1.2;
  co.camera.footprint_h_m = 0.8;
  const FootprintCamera camera(co);
  CoverageCriteria criteria;
  criteria.max_incidence_deg = 75.0;
  const PostBlocker post;
  const MultiViewStats st = multiViewStats(pts, {Vec3::UnitX()}, views, camera, criteria, &post, 2);
  ASSERT_EQ(st.points, pts.size());
  ASSERT_EQ(st.views.size(), pts.size());
  std::vector<int> counts;
  std::vector<double> angles;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    std::vector<Vec3> rays;
    for (const auto& v : views) {
      if (sees(v, pts[i], 1.2, 0.8, 1.5, 1.5, 75.0, post)) rays.push_back(v.position - pts[i]);
    }
    double angle = 0.0;
    for (std::size_t a = 0; a < rays.size(); ++a)
      for (std::size_t b = a + 1; b < rays.size(); ++b)
        angle = std::max(angle, std::acos(std::clamp(rays[a].normalized().dot(rays[b].normalized()),
                                                     -1.0, 1.0)) /
                                    kDeg);
    EXPECT_EQ(st.views[i], static_cast<int>(rays.size())) << "point " << i;
    EXPECT_NEAR(st.angle_deg[i], angle, 1e-9) << "point " << i;
    counts.push_back(static_cast<int>(rays.size()));
    angles.push_back(angle);
  }
  std::sort(counts.begin(), counts.end());
  std::sort(angles.begin(), angles.end());
  EXPECT_EQ(st.views_min, counts.front());
  EXPECT_EQ(st.views_median, counts[(counts.size() - 1) / 2]);
  EXPECT_NEAR(st.angle_min_deg, angles.front(), 1e-9);
  EXPECT_NEAR(st.angle_median_deg, angles[(angles.size() - 1) / 2], 1e-9);
  EXPECT_GE(counts.back(), 3);  // the scene does hold multi-view points
  // The post hides part of the wall from some camera: a count differs with it.
  const MultiViewStats open =
      multiViewStats(pts, {Vec3::UnitX()}, views, camera, criteria, nullptr, 1);
  int differ = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) differ += open.views[i] != st.views[i] ? 1 : 0;
  EXPECT_GT(differ, 0);
}

/// A w x h m wall in the plane x = 0 facing +x: y in [-w/2, w/2], z in [0, h].
Surface wall(double w, double h) {
  Surface s;
  s.id = 1;
  s.plane.normal = Vec3::UnitX();
  s.plane.offset = 0.0;
  s.boundary = {Vec3(0, -0.5 * w, 0), Vec3(0, 0.5 * w, 0), Vec3(0, 0.5 * w, h),
                Vec3(0, -0.5 * w, h)};
  s.inliers = s.boundary;
  s.centroid = Vec3(0, 0, 0.5 * h);
  s.axis_u = Vec3::UnitY();
  s.axis_v = s.plane.normal.cross(s.axis_u);
  s.area_m2 = w * h;
  s.density_area_m2 = w * h;
  return s;
}

/// A hand-built 2 m x 1 m wall facing +x (the plane x = 0, y in [-1, 1], z in [0, 1]).
Surface smallWall() { return wall(2.0, 1.0); }

/// Share of footprint a's rectangle (fw x fh about its target, in y and z) that b's holds.
double sharedShare(const Stop& a, const Stop& b, double fw, double fh) {
  const double oy = std::max(0.0, fw - std::abs(a.target.y() - b.target.y()));
  const double oz = std::max(0.0, fh - std::abs(a.target.z() - b.target.z()));
  return oy * oz / (fw * fh);
}

/// Brute force over points every `step` m inside a w x h wall (off its edges by half a
/// step): the least count of footprints (fw x fh about each stop's target) holding a
/// point, and the least of the points' largest angle between two of their rays [deg].
std::pair<int, double> leastViews(const FlightStrategy& fs, double w, double h, double fw,
                                  double fh, double step) {
  int min_views = 1 << 20;
  double min_angle = 180.0;
  for (double y = -0.5 * w + 0.5 * step; y < 0.5 * w; y += step) {
    for (double z = 0.5 * step; z < h; z += step) {
      const Vec3 p(0.0, y, z);
      std::vector<Vec3> rays;
      for (const auto& s : fs.stops) {
        if (std::abs(p.y() - s.target.y()) <= 0.5 * fw &&
            std::abs(p.z() - s.target.z()) <= 0.5 * fh)
          rays.push_back((s.position - p).normalized());
      }
      double angle = 0.0;
      for (std::size_t a = 0; a < rays.size(); ++a)
        for (std::size_t b = a + 1; b < rays.size(); ++b)
          angle = std::max(angle, std::acos(std::clamp(rays[a].dot(rays[b]), -1.0, 1.0)) / kDeg);
      min_views = std::min(min_views, static_cast<int>(rays.size()));
      min_angle = std::min(min_angle, angle);
    }
  }
  return {min_views, min_angle};
}

TEST(MultiView, ReconstructionPlanMeetsItsTargets) {
  // Walls narrower than a footprint, about one, a few, and single_plane's 8 x 4 m; the
  // paper's 0.6 x 0.4 m footprint at 1.5 m, side overlap 0.2 (the default) and 0.
  struct Case {
    double w, h;
    int views;
    double overlap;
  };
  const std::vector<Case> cases = {{2.0, 1.0, 3, 0.2},  {2.0, 1.0, 5, 0.2}, {2.0, 1.0, 2, 0.0},
                                   {0.25, 0.3, 3, 0.2}, {0.5, 1.3, 3, 0.2}, {0.7, 0.5, 4, 0.0},
                                   {1.1, 0.9, 2, 0.2},  {3.3, 0.4, 3, 0.0}, {8.0, 4.0, 3, 0.2}};
  for (const Case& c : cases) {
    CoverageOptions o;
    o.purpose = "reconstruction";
    o.min_views = c.views;
    o.overlap_h = c.overlap;
    const FlightStrategy fs = planFlightStrategy(wall(c.w, c.h), o);
    const std::string what = std::to_string(c.w) + " x " + std::to_string(c.h) + " m, " +
                             std::to_string(c.views) + " views";
    ASSERT_FALSE(fs.stops.empty()) << what;
    const auto [min_views, min_angle] = leastViews(fs, c.w, c.h, 0.6, 0.4, c.w > 4.0 ? 0.02 : 0.01);
    EXPECT_GE(min_views, c.views) << what;
    if (c.views > 1) {
      EXPECT_GE(min_angle, o.min_triangulation_deg) << what;
    }
    for (std::size_t i = 1; i < fs.stops.size(); ++i) {
      EXPECT_GE(sharedShare(fs.stops[i - 1], fs.stops[i], 0.6, 0.4), kReconstructionShare - 1e-9)
          << what << ", stops " << i - 1 << ", " << i;
      EXPECT_NEAR(footprintShare(fs, fs.stops[i - 1], fs.stops[i]),
                  sharedShare(fs.stops[i - 1], fs.stops[i], 0.6, 0.4), 1e-9);
      EXPECT_EQ(fs.stops[i].index, static_cast<int>(i));
    }
    for (const auto& s : fs.stops) {
      EXPECT_NEAR((s.position - s.target).norm(), 1.5, 1e-9);
      EXPECT_LE(std::abs(s.target.y()), 0.5 * c.w) << what;
      EXPECT_GE(s.target.z(), 0.0) << what;
      EXPECT_LE(s.target.z(), c.h) << what;
    }
  }
}

TEST(MultiView, ReconstructionCostsLittleMoreThanItsCountingBound) {
  // single_plane's 8 x 4 m wall, the paper's camera, 3 views at the default side
  // overlap 0.2: the counting bound is 3 x 32 / 0.24 = 400 photos. Rows of photos a
  // third of a footprint apart, the rows 0.8 of a footprint apart (13 rows: 12.5 of
  // them span the wall), a few more at each row's ends and one between rows take
  // 13 x 44 + 12 = 584 (1.46 x); a grid 0.4 of a footprint apart on both axes (the
  // 60 % share on both) would take 35 x 26 = 910 (2.3 x).
  CoverageOptions o;
  o.purpose = "reconstruction";
  const FlightStrategy fs = planFlightStrategy(wall(8.0, 4.0), o);
  const double bound = 3.0 * 32.0 / (0.6 * 0.4);
  EXPECT_LE(static_cast<double>(fs.stops.size()), 1.5 * bound) << fs.stops.size();
  // With no side overlap the rows meet edge to edge (10 rows, two photos between
  // each): 10 x 44 + 18 = 458 (1.15 x).
  o.overlap_h = 0.0;
  const FlightStrategy tight = planFlightStrategy(wall(8.0, 4.0), o);
  EXPECT_LE(static_cast<double>(tight.stops.size()), 1.2 * bound) << tight.stops.size();
  EXPECT_EQ(tight.rows, 10);
}

/// Sees everything.
class OpenSight final : public LineOfSight {
 public:
  bool clear(const Vec3&, const Vec3&) const override { return true; }
};

/// The least count of fs's photos (0.6 x 0.4 m at 1.5 m) that see a point `depth` [m] in
/// front of the wall x = 0, over y in [y_lo, y_hi] every `y_step` and z in [0, 2] every
/// 5 mm: brute force through each frustum (sees).
int leastViewsInFront(const FlightStrategy& fs, double depth, double y_lo, double y_hi,
                      double y_step) {
  const OpenSight open;
  std::vector<ViewPose> views;
  for (const auto& st : fs.stops) views.push_back({st.position, st.yaw_deg, st.gimbal_pitch_deg});
  int least = 1 << 20;
  for (double y = y_lo; y <= y_hi + 1e-9; y += y_step) {
    for (int k = 0; k <= 400; ++k) {
      const Vec3 p(depth, y, 0.005 * k);
      int n = 0;
      for (const auto& v : views) n += sees(v, p, 0.6, 0.4, 1.5, 2.0, 89.0, open) ? 1 : 0;
      least = std::min(least, n);
    }
  }
  return least;
}

TEST(MultiView, ReconstructionRowsKeepAMarginForPointsOffThePlane) {
  // A scan's points lie a little off the fitted plane. Points 5 cm in front of a 3 x 2 m
  // wall, every 5 mm across the rows' seams, away from the rows' ends (the columns'
  // own margin, kEdgeMargin, is not at test here), counted through each photo's
  // frustum by brute force (sees): rows edge to edge (side overlap 0: five rows, seams
  // at 0.4 m steps) leave the seams' points in no photo (a row's photos share its
  // height); a side overlap of 0.2 (CoverageOptions' default; the app's reconstruction
  // takes the inliers' own margin, next test) keeps them in min_views. A margin under
  // 5 cm / 1.5 m = 0.033 would not: single_plane's scan at 0 left 240 points below.
  for (const double overlap : {0.0, CoverageOptions{}.overlap_h}) {
    CoverageOptions o;
    o.purpose = "reconstruction";
    o.overlap_w = overlap;
    o.overlap_h = overlap;
    const FlightStrategy fs = planFlightStrategy(wall(3.0, 2.0), o);
    const int least = leastViewsInFront(fs, 0.05, -1.2, 1.2, 0.1);
    if (overlap > 0.0) {
      EXPECT_GE(least, o.min_views) << "overlap " << overlap;
    } else {
      EXPECT_LT(least, o.min_views) << "rows edge to edge";
    }
  }
}

TEST(MultiView, ReconstructionRowsOverlapByWhatTheInliersInFrontNeed) {
  // The same 3 x 2 m wall, its inliers every 5 cm on the plane and every tenth of them
  // 5 cm in front (the scan's noise); the file's overlap 0. The rows overlap by what
  // those points need (5 cm / 1.5 m of a footprint): brute force through each frustum
  // finds every point 4.9 cm in front (the seams meet exactly at 5 cm) in min_views
  // photos, seams, ends and edges included, with fewer
  // photos than the old default (side overlap 0.2). One stray inlier 1 m out (above the
  // 99.9th percentile) changes nothing.
  Surface noisy = wall(3.0, 2.0);
  noisy.inliers.clear();
  int k = 0;
  for (double y = -1.5; y <= 1.5 + 1e-9; y += 0.05)
    for (double z = 0.0; z <= 2.0 + 1e-9; z += 0.05)
      noisy.inliers.emplace_back(++k % 10 == 0 ? 0.05 : 0.0, y, z);
  CoverageOptions o;
  o.purpose = "reconstruction";
  o.overlap_w = o.overlap_h = 0.0;
  const FlightStrategy fs = planFlightStrategy(noisy, o);
  EXPECT_GE(leastViewsInFront(fs, 0.049, -1.5, 1.5, 0.01), o.min_views);
  CoverageOptions old = o;
  old.overlap_w = old.overlap_h = 0.2;
  EXPECT_LT(fs.stops.size(), planFlightStrategy(wall(3.0, 2.0), old).stops.size());
  Surface stray = noisy;
  stray.inliers.emplace_back(1.0, 0.0, 1.0);
  const FlightStrategy same = planFlightStrategy(stray, o);
  ASSERT_EQ(same.stops.size(), fs.stops.size());
  for (std::size_t i = 0; i < fs.stops.size(); ++i)
    EXPECT_EQ(same.stops[i].position, fs.stops[i].position) << "stop " << i;
}

/// Points every `step` m inside a w x h wall (as leastViews) that fewer than `views`
/// footprints (fw x fh about each stop's target) hold, and how many they miss: brute
/// force.
std::pair<PointList, std::vector<int>> pointsBelow(const FlightStrategy& fs, double w, double h,
                                                   int views, double step) {
  std::pair<PointList, std::vector<int>> low;
  for (double y = -0.5 * w + 0.5 * step; y < 0.5 * w; y += step) {
    for (double z = 0.5 * step; z < h; z += step) {
      const auto n = std::count_if(fs.stops.begin(), fs.stops.end(), [&](const Stop& s) {
        return std::abs(y - s.target.y()) <= 0.3 && std::abs(z - s.target.z()) <= 0.2;
      });
      if (n < views) {
        low.first.emplace_back(0.0, y, z);
        low.second.push_back(views - static_cast<int>(n));
      }
    }
  }
  return low;
}

TEST(MultiView, TopUpStopsGiveEveryPointItsViewsBack) {
  // A 3 x 2 m wall's reconstruction with three neighbouring stops of a middle row left
  // out (as stops the obstacle repair could not place): brute force finds points below
  // min_views; addStopsFor, given them and what they miss, adds stops square at the
  // standoff aimed at them until no point is below (at most 3 rounds, as the
  // pipeline's top-up), at most two more than were left out, each flown where it and
  // both its neighbours share kReconstructionShare of their footprints (the 60 %).
  CoverageOptions o;
  o.purpose = "reconstruction";
  FlightStrategy fs = planFlightStrategy(wall(3.0, 2.0), o);
  const std::size_t planned = fs.stops.size();
  const std::size_t mid = planned / 2;
  fs.stops.erase(fs.stops.begin() + static_cast<std::ptrdiff_t>(mid) - 1,
                 fs.stops.begin() + static_cast<std::ptrdiff_t>(mid) + 2);
  auto low = pointsBelow(fs, 3.0, 2.0, o.min_views, 0.02);
  ASSERT_FALSE(low.first.empty());
  const Surface surface = wall(3.0, 2.0);
  int rounds = 0;
  for (; rounds < 3 && !low.first.empty(); ++rounds) {
    const std::size_t before = fs.stops.size();
    const std::size_t added = addStopsFor(fs, surface, low.first, low.second);
    EXPECT_EQ(added, fs.stops.size() - before);
    low = pointsBelow(fs, 3.0, 2.0, o.min_views, 0.02);
  }
  EXPECT_TRUE(low.first.empty()) << low.first.size() << " points below after " << rounds
                                 << " rounds";
  EXPECT_LE(fs.stops.size(), planned + 2);
  for (std::size_t i = 0; i < fs.stops.size(); ++i) {
    const Stop& s = fs.stops[i];
    EXPECT_EQ(s.index, static_cast<int>(i));
    EXPECT_NEAR(s.target.x(), 0.0, 1e-9);
    EXPECT_TRUE((s.position - (s.target + 1.5 * Vec3::UnitX())).norm() < 1e-9) << "stop " << i;
    if (i > 0) {
      EXPECT_GE(sharedShare(fs.stops[i - 1], s, 0.6, 0.4), kReconstructionShare - 1e-9)
          << "stop " << i;
    }
  }
  // Nothing short: nothing changes.
  const std::size_t topped = fs.stops.size();
  EXPECT_EQ(addStopsFor(fs, surface, {}, {}), 0u);
  EXPECT_EQ(fs.stops.size(), topped);
}

TEST(MultiView, ATopUpStopBetweenRowsIsBridged) {
  // Points short of one view on the seam between the first two rows, mid-wall: the stop
  // aimed at them stands half a row off both rows, sharing about half a footprint with
  // any row stop, so photos must join it to the order (every consecutive pair shares
  // kReconstructionShare, brute force on the targets), and one on each side does.
  CoverageOptions o;
  o.purpose = "reconstruction";
  o.overlap_w = o.overlap_h = 0.0;  // the app's reconstruction default (no file overlap)
  const Surface surface = wall(3.0, 2.0);
  FlightStrategy fs = planFlightStrategy(surface, o);
  double z0 = 0.0, z1 = 0.0;
  int n0 = 0, n1 = 0;
  for (const Stop& s : fs.stops) {
    if (s.row == 0) z0 += s.target.z(), ++n0;
    if (s.row == 1) z1 += s.target.z(), ++n1;
  }
  ASSERT_GT(n0, 0);
  ASSERT_GT(n1, 0);
  const double seam = 0.5 * (z0 / n0 + z1 / n1);
  ASSERT_GT(z1 / n1 - z0 / n0, 0.3);  // rows most of a footprint apart
  PointList points;
  for (double dy = -0.02; dy <= 0.0201; dy += 0.01) points.emplace_back(0.0, 0.1 + dy, seam);
  const std::vector<int> missing(points.size(), 1);
  const std::size_t before = fs.stops.size();
  const std::size_t added = addStopsFor(fs, surface, points, missing);
  EXPECT_EQ(added, fs.stops.size() - before);
  EXPECT_LE(added, 3u);
  EXPECT_TRUE(std::any_of(fs.stops.begin(), fs.stops.end(), [&](const Stop& s) {
    return std::abs(s.target.y() - 0.1) <= 0.24 && std::abs(s.target.z() - seam) <= 0.16;
  }));
  for (std::size_t i = 1; i < fs.stops.size(); ++i) {
    EXPECT_EQ(fs.stops[i].index, static_cast<int>(i));
    EXPECT_GE(sharedShare(fs.stops[i - 1], fs.stops[i], 0.6, 0.4), kReconstructionShare - 1e-9)
        << "stops " << i - 1 << " and " << i;
  }
}

TEST(MultiView, InspectionAndMosaicKeepThePaperRows) {
  const Surface wall = smallWall();
  CoverageOptions o;
  const FlightStrategy paper = planFlightStrategy(wall, o);
  for (const char* purpose : {"inspection", "mosaic"}) {
    o.purpose = purpose;  // mosaic's own overlap is the app's default, not the planner's
    const FlightStrategy fs = planFlightStrategy(wall, o);
    ASSERT_EQ(fs.stops.size(), paper.stops.size()) << purpose;
    EXPECT_EQ(fs.spacing_w_m, paper.spacing_w_m);
    EXPECT_EQ(fs.spacing_h_m, paper.spacing_h_m);
    for (std::size_t i = 0; i < fs.stops.size(); ++i) {
      EXPECT_EQ(fs.stops[i].position, paper.stops[i].position) << purpose << " stop " << i;
      EXPECT_EQ(fs.stops[i].target, paper.stops[i].target);
    }
  }
}

}  // namespace
}  // namespace uavip::coverage
