#include "uavip/sim/scanner_sim.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <sstream>

#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/memory.h"
#include "uavip/core/random.h"
#include "uavip/core/text.h"

namespace uavip::sim {
namespace {

constexpr double kDeg = kDegToRad;
/// Hits closer than this to the ray origin are ignored (self-intersection guard) [m].
constexpr double kMinHit = 1e-9;
/// Leaves of the BVH hold at most this many shapes.
constexpr int kLeafSize = 4;

void requireNonNegative(double v, const std::string& where, const std::string& name) {
  if (!(std::isfinite(v) && v >= 0.0)) {
    std::ostringstream os;
    os << where << ": " << name << " must be >= 0, got " << v;
    throw InputError(os.str());
  }
}

/// Throws InputError unless v <= max: "<where>: <name> must be <= <max_text>, got <v>".
void requireAtMost(double v, double max, const char* max_text, const std::string& where,
                   const std::string& name) {
  require(v <= max, where, name + " must be <= " + max_text + ", got " + std::to_string(v));
}

Eigen::Matrix3d rpy(const Vec3& rpy_deg) {
  return (Eigen::AngleAxisd(rpy_deg.z() * kDeg, Vec3::UnitZ()) *
          Eigen::AngleAxisd(rpy_deg.y() * kDeg, Vec3::UnitY()) *
          Eigen::AngleAxisd(rpy_deg.x() * kDeg, Vec3::UnitX()))
      .toRotationMatrix();
}

/// Ray–sphere: entry distance, or +inf.
double hitSphere(const Vec3& o, const Vec3& d, const Vec3& c, double r) {
  const Vec3 oc = o - c;
  const double b = d.dot(oc);
  const double h = b * b - (oc.squaredNorm() - r * r);
  if (h < 0.0) return kInf;
  const double t = -b - std::sqrt(h);
  if (t > kMinHit) return t;
  return kInf;
}

/// Ray–capsule (segment pa–pb, radius r): entry distance, or +inf. The body is the
/// cylinder quadric restricted to the segment; otherwise the nearer end cap sphere.
double hitCapsule(const Vec3& o, const Vec3& d, const Vec3& pa, const Vec3& pb, double r) {
  const Vec3 ba = pb - pa;
  const Vec3 oa = o - pa;
  const double baba = ba.dot(ba), bard = ba.dot(d), baoa = ba.dot(oa);
  const double rdoa = d.dot(oa), oaoa = oa.dot(oa);
  const double a = baba - bard * bard;
  double best = kInf;
  if (a > 1e-12 * baba) {
    const double b = baba * rdoa - baoa * bard;
    const double c = baba * oaoa - baoa * baoa - r * r * baba;
    const double h = b * b - a * c;
    if (h < 0.0) return kInf;  // the infinite cylinder is missed, so are the caps
    const double t = (-b - std::sqrt(h)) / a;
    const double y = baoa + t * bard;
    if (y > 0.0 && y < baba && t > kMinHit) return t;
  }
  best = std::min(hitSphere(o, d, pa, r), hitSphere(o, d, pb, r));
  return best;
}

/// Slab test: entry distance of the ray into the box if below `best`, else +inf.
double hitBox(const Vec3& o, const Vec3& inv, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
              double best) {
  double t0 = 0.0, t1 = best;
  for (int k = 0; k < 3; ++k) {
    double a = (lo[k] - o[k]) * inv[k];
    double b = (hi[k] - o[k]) * inv[k];
    if (a > b) std::swap(a, b);
    // NaN (0 · inf when the origin is on a slab plane) must not reject: max/min keep t.
    if (a > t0) t0 = a;
    if (b < t1) t1 = b;
    if (t0 > t1) return kInf;
  }
  return t0;
}

/// A bounded random walk sampled every tick (3 axes), 0 at tick 0.
std::vector<Vec3> boundedWalk(std::mt19937& rng, int ticks, double step, double bound) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<Vec3> w(static_cast<std::size_t>(ticks), Vec3::Zero());
  for (int k = 1; k < ticks; ++k) {
    for (int a = 0; a < 3; ++a) {
      const double g = gauss(rng);  // drawn even when step is 0: same stream either way
      w[k][a] = std::clamp(w[k - 1][a] + step * g, -bound, bound);
    }
  }
  return w;
}

/// The true motion of one station: yaw ramp, wind offset and tilt walks.
class StationMotion {
 public:
  StationMotion(const ScanSimOptions& o, const Vec3& position, double t0, double span_s,
                std::mt19937& rng)
      : position_(position),
        t0_(t0),
        tick_(o.scanner.period_s),
        yaw0_(o.start_yaw_deg * kDeg),
        yaw_rate_(o.yaw_rate_deg_s * kDeg) {
    const int ticks = static_cast<int>(std::ceil(span_s / tick_)) + 2;
    wind_ = boundedWalk(rng, ticks, o.wind_step_m, o.wind_bound_m);
    tilt_ = boundedWalk(rng, ticks, o.tilt_step_deg * kDeg, o.tilt_bound_deg * kDeg);
    for (auto& v : tilt_) v.z() = 0.0;  // only roll (x) and pitch (y) tilt
  }

  /// world_T_body at absolute time t (log frame when position_ is).
  Eigen::Isometry3d pose(double t) const {
    const double local = std::max(0.0, t - t0_);
    const double f = local / tick_;
    const std::size_t k = std::min(static_cast<std::size_t>(f), wind_.size() - 2);
    const double w = std::min(1.0, f - static_cast<double>(k));
    const Vec3 wind = (1.0 - w) * wind_[k] + w * wind_[k + 1];
    const Vec3 tilt = (1.0 - w) * tilt_[k] + w * tilt_[k + 1];
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() =
        (Eigen::AngleAxisd(yaw0_ + yaw_rate_ * local, Vec3::UnitZ()) *
         Eigen::AngleAxisd(tilt.y(), Vec3::UnitY()) * Eigen::AngleAxisd(tilt.x(), Vec3::UnitX()))
            .toRotationMatrix();
    T.translation() = position_ + wind;
    return T;
  }

 private:
  Vec3 position_;
  double t0_, tick_, yaw0_, yaw_rate_;
  std::vector<Vec3> wind_, tilt_;
};

/// Beam direction in the scanner frame (core/raw_log.h): eq. (1) for the vertical
/// scanner, the x*–y* plane for the horizontal one.
Vec3 beamDir(bool vertical, double alpha) {
  return vertical ? Vec3(-std::cos(alpha), 0.0, -std::sin(alpha))
                  : Vec3(std::cos(alpha), std::sin(alpha), 0.0);
}

}  // namespace

// ---------------------------------------------------------------- ScannerModel

int ScannerModel::beamCount() const {
  return static_cast<int>(std::lround(fov_deg / step_deg)) + 1;
}
double ScannerModel::angleMinRad() const { return -0.5 * fov_deg * kDeg; }
double ScannerModel::angleStepRad() const { return step_deg * kDeg; }
double ScannerModel::sweepDurationS() const { return period_s * fov_deg / 360.0; }

void ScannerModel::validate(const std::string& where) const {
  requirePositive(max_range_m, where, "max_range_m");
  requireNonNegative(min_range_m, where, "min_range_m");
  require(min_range_m < max_range_m, where,
          "min_range_m must be < max_range_m, got " + std::to_string(min_range_m) + " and " +
              std::to_string(max_range_m));
  requirePositive(fov_deg, where, "fov_deg");
  requireAtMost(fov_deg, 360.0, "360", where, "fov_deg");
  requirePositive(step_deg, where, "step_deg");
  require(fov_deg / step_deg <= 100000.0, where, "fov_deg / step_deg must be <= 100000 beams");
  requirePositive(period_s, where, "period_s");
  requireNonNegative(range_noise_m, where, "range_noise_m");
}

// ---------------------------------------------------------------- ScanSimOptions

Eigen::Isometry3d ScanSimOptions::bodyTVertical() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rpy(vertical_mount_rpy_deg);
  T.translation() = vertical_mount_m;
  return T;
}

Eigen::Isometry3d ScanSimOptions::bodyTHorizontal() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rpy(horizontal_mount_rpy_deg);
  T.translation() = horizontal_mount_m;
  return T;
}

int ScanSimOptions::scansPerStation() const {
  return static_cast<int>(std::floor(turn_deg / (yaw_rate_deg_s * scanner.period_s) + 1e-9)) + 1;
}

void ScanSimOptions::validate(const std::string& where) const {
  require(!stations.empty(), where, "stations must list at least one [x, y, z] station");
  for (const auto& s : stations) require(s.allFinite(), where, "stations must be finite");
  scanner.validate(where);
  require(std::isfinite(start_yaw_deg), where, "start_yaw_deg must be finite");
  requirePositive(yaw_rate_deg_s, where, "yaw_rate_deg_s");
  requirePositive(turn_deg, where, "turn_deg");
  require(turn_deg <= 3600.0, where, "turn_deg must be <= 3600, got " + std::to_string(turn_deg));
  require(turn_deg / (yaw_rate_deg_s * scanner.period_s) <= 1e6, where,
          "turn_deg / (yaw_rate_deg_s * period) must be <= 1e6 scans per station");
  requirePositive(max_readings, where, "max_readings");
  const double readings = static_cast<double>(stations.size()) *
                          (turn_deg / (yaw_rate_deg_s * scanner.period_s) + 1.0) * 2.0 *
                          scanner.beamCount();
  require(readings <= max_readings, where,
          formatNumber(static_cast<double>(stations.size())) + " stations x " +
              formatNumber(turn_deg) + " deg at " + formatNumber(yaw_rate_deg_s) + " deg/s make " +
              formatNumber(readings / 1e6, 3) +
              " M range readings, more than max_readings = " + formatNumber(max_readings / 1e6, 3) +
              " M; use fewer stations, a smaller turn_deg or a faster yaw_rate_deg_s, or raise "
              "sensing.max_readings");
  for (const Vec3* v : {&vertical_mount_m, &horizontal_mount_m, &vertical_mount_rpy_deg,
                        &horizontal_mount_rpy_deg}) {
    require(v->allFinite(), where, "mount offsets and angles must be finite");
  }
  requireNonNegative(horizontal_time_offset_s, where, "horizontal_time_offset_s");
  require(horizontal_time_offset_s < scanner.period_s, where,
          "horizontal_time_offset_s must be < the scan period " + std::to_string(scanner.period_s) +
              " s");
  requirePositive(imu_rate_hz, where, "imu_rate_hz");
  requireAtMost(imu_rate_hz, 10000.0, "10000", where, "imu_rate_hz");
  requireNonNegative(imu_error_deg, where, "imu_error_deg");
  requireAtMost(imu_error_deg, 45.0, "45", where, "imu_error_deg");
  requireNonNegative(wind_step_m, where, "wind_step_m");
  requireNonNegative(wind_bound_m, where, "wind_bound_m");
  requireNonNegative(tilt_step_deg, where, "tilt_step_deg");
  requireNonNegative(tilt_bound_deg, where, "tilt_bound_deg");
  requireAtMost(tilt_bound_deg, 30.0, "30", where, "tilt_bound_deg");
  requireNonNegative(gps_sigma_m, where, "gps_sigma_m");
  requireNonNegative(thin_radius_m, where, "thin_radius_m");
  requireNonNegative(station_gap_s, where, "station_gap_s");
}

// ---------------------------------------------------------------- ray casting

double intersectRayRect(const Vec3& origin, const Vec3& dir, const Rect& rect) {
  const Vec3 n = rect.edge_u.cross(rect.edge_v);
  const double denom = n.dot(dir);
  if (denom == 0.0 || !std::isfinite(denom)) return kInf;
  const double t = n.dot(rect.corner - origin) / denom;
  if (!(t > kMinHit)) return kInf;
  const Vec3 q = origin + t * dir - rect.corner;
  const double s = q.dot(rect.edge_u) / rect.edge_u.squaredNorm();
  const double r = q.dot(rect.edge_v) / rect.edge_v.squaredNorm();
  if (s >= 0.0 && s <= 1.0 && r >= 0.0 && r <= 1.0) return t;
  return kInf;
}

RayCaster::RayCaster(const WorldModel& world, double thin_radius_m) : radius_(thin_radius_m) {
  require(std::isfinite(thin_radius_m) && thin_radius_m >= 0.0, "ray caster",
          "thin_radius_m must be >= 0, got " + std::to_string(thin_radius_m));
  std::vector<Eigen::Vector3d> lo, hi;
  const double pad = 1e-6;  // flat rectangles get a thin box
  for (const Rect& r : world.rects()) {
    kinds_.push_back(Kind::Rect);
    a_.push_back(r.corner);
    b_.push_back(r.edge_u / r.edge_u.squaredNorm());
    c_.push_back(r.edge_v / r.edge_v.squaredNorm());
    n_.push_back(r.normal());
    Vec3 l = r.corner, h = r.corner;
    for (const Vec3& p : {Vec3(r.corner + r.edge_u), Vec3(r.corner + r.edge_v),
                          Vec3(r.corner + r.edge_u + r.edge_v)}) {
      l = l.cwiseMin(p);
      h = h.cwiseMax(p);
    }
    lo.push_back(l.array() - pad);
    hi.push_back(h.array() + pad);
  }
  if (radius_ > 0.0) {
    for (const Segment& s : world.segments()) {
      kinds_.push_back(Kind::Capsule);
      a_.push_back(s.a);
      b_.push_back(s.b);
      c_.push_back(Vec3::Zero());
      n_.push_back(Vec3::Zero());
      lo.push_back(s.a.cwiseMin(s.b).array() - radius_ - pad);
      hi.push_back(s.a.cwiseMax(s.b).array() + radius_ + pad);
    }
    for (const TruthPoint& p : world.points()) {
      kinds_.push_back(Kind::Sphere);
      a_.push_back(p.p);
      b_.push_back(Vec3::Zero());
      c_.push_back(Vec3::Zero());
      n_.push_back(Vec3::Zero());
      lo.push_back(p.p.array() - radius_ - pad);
      hi.push_back(p.p.array() + radius_ + pad);
    }
  }
  if (kinds_.empty()) return;
  std::vector<int> order(kinds_.size());
  std::iota(order.begin(), order.end(), 0);
  nodes_.reserve(2 * kinds_.size());
  build(order, 0, static_cast<int>(order.size()), lo, hi);
  // Store shapes in leaf order so leaves index contiguous ranges.
  auto permute = [&order](auto& v) {
    auto copy = v;
    for (std::size_t i = 0; i < order.size(); ++i) v[i] = copy[static_cast<std::size_t>(order[i])];
  };
  permute(kinds_);
  permute(a_);
  permute(b_);
  permute(c_);
  permute(n_);
}

int RayCaster::build(std::vector<int>& order, int begin, int end,
                     const std::vector<Eigen::Vector3d>& lo,
                     const std::vector<Eigen::Vector3d>& hi) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back({});
  Eigen::Vector3d l = lo[static_cast<std::size_t>(order[static_cast<std::size_t>(begin)])];
  Eigen::Vector3d h = hi[static_cast<std::size_t>(order[static_cast<std::size_t>(begin)])];
  for (int i = begin; i < end; ++i) {
    l = l.cwiseMin(lo[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])]);
    h = h.cwiseMax(hi[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])]);
  }
  nodes_[static_cast<std::size_t>(index)].lo = l;
  nodes_[static_cast<std::size_t>(index)].hi = h;
  if (end - begin <= kLeafSize) {
    nodes_[static_cast<std::size_t>(index)].first = begin;
    nodes_[static_cast<std::size_t>(index)].count = end - begin;
    return index;
  }
  // Median split of the box centres on the longest axis.
  int axis = 0;
  (h - l).maxCoeff(&axis);
  const int mid = (begin + end) / 2;
  auto centre = [&](int s) {
    return lo[static_cast<std::size_t>(s)][axis] + hi[static_cast<std::size_t>(s)][axis];
  };
  std::nth_element(
      order.begin() + begin, order.begin() + mid, order.begin() + end,
      [&](int x, int y) { return centre(x) < centre(y) || (centre(x) == centre(y) && x < y); });
  const int left = build(order, begin, mid, lo, hi);
  const int right = build(order, mid, end, lo, hi);
  nodes_[static_cast<std::size_t>(index)].first = left;
  nodes_[static_cast<std::size_t>(index)].count = 0;
  nodes_[static_cast<std::size_t>(index)].right = right;
  return index;
}

double RayCaster::hitShape(int i, const Vec3& o, const Vec3& d, double best) const {
  const auto k = static_cast<std::size_t>(i);
  switch (kinds_[k]) {
    case Kind::Rect: {
      const double denom = n_[k].dot(d);
      if (denom == 0.0) return kInf;
      const double t = n_[k].dot(a_[k] - o) / denom;
      if (!(t > kMinHit) || t >= best) return kInf;
      const Vec3 q = o + t * d - a_[k];
      const double s = q.dot(b_[k]);
      const double r = q.dot(c_[k]);
      if (s >= 0.0 && s <= 1.0 && r >= 0.0 && r <= 1.0) return t;
      return kInf;
    }
    case Kind::Capsule:
      return hitCapsule(o, d, a_[k], b_[k], radius_);
    case Kind::Sphere:
      return hitSphere(o, d, a_[k], radius_);
  }
  return kInf;
}

double RayCaster::cast(const Vec3& origin, const Vec3& dir, double max_range_m) const {
  if (nodes_.empty()) return kInf;
  const Vec3 inv = dir.cwiseInverse();  // ±inf for axis-parallel rays is what the slab test wants
  double best = max_range_m;
  bool hit = false;
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[static_cast<std::size_t>(stack[--top])];
    if (hitBox(origin, inv, node.lo, node.hi, best) == kInf) continue;
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const double t = hitShape(i, origin, dir, best);
        if (t <= best) {
          best = t;
          hit = true;
        }
      }
    } else if (top + 2 <= 64) {
      stack[top++] = node.right;
      stack[top++] = node.first;
    }
  }
  if (hit) return best;
  return kInf;
}

// ---------------------------------------------------------------- simulation

namespace {

/// What every station of one sweep shares: the options, the caster, the timing and
/// the two distributions (drawn from in the original order: the normal distribution
/// keeps a spare value between calls, so it is one object for the whole sweep).
struct Sweep {
  Sweep(const ScanSimOptions& options, const RayCaster& ray_caster)
      : o(options),
        caster(ray_caster),
        beams(options.scanner.beamCount()),
        scans(options.scansPerStation()),
        mounts{options.bodyTVertical(), options.bodyTHorizontal()} {
    const ScannerModel& sc = o.scanner;
    const double turn_s = o.turn_deg / o.yaw_rate_deg_s;
    span_s = (scans - 1) * sc.period_s + o.horizontal_time_offset_s + sc.sweepDurationS();
    station_s = turn_s + sc.period_s + o.station_gap_s;
  }

  const ScanSimOptions& o;
  const RayCaster& caster;
  int beams;
  int scans;
  Eigen::Isometry3d mounts[2];  ///< body ← vertical, body ← horizontal scanner
  double span_s{0.0};           ///< first scan start to past the last beam [s]
  double station_s{0.0};        ///< station start to the next one's [s]
  std::uniform_real_distribution<double> unit{0.0, 1.0};
  std::normal_distribution<double> gauss{0.0, 1.0};
};

/// Recorded (GPS-like) position and heading of station s at `position` (log frame).
void recordStation(Sweep& w, std::size_t s, const Vec3& position, Station& st) {
  const ScanSimOptions& o = w.o;
  std::seed_seq gps_seed{o.seed, static_cast<std::uint32_t>(s), 1u};
  std::mt19937 gps_rng(gps_seed);
  auto& gauss = w.gauss;
  const Vec3 gps_error = drawVec3(gauss, gps_rng);
  st.recorded_position = s == 0 ? Vec3::Zero() : Vec3(position + o.gps_sigma_m * gps_error);
  st.recorded_yaw_rad =
      o.start_yaw_deg * kDeg + o.imu_error_deg * kDeg * (2.0 * w.unit(gps_rng) - 1.0);
}

/// Scan i of scanner k (0 vertical, 1 horizontal) of station s starting at t0; its
/// start pose goes to `poses`. `dirs` are the beam directions in the body frame.
LaserScan simulateScan(Sweep& w, std::size_t s, int k, int i, double t0,
                       const StationMotion& motion, const std::vector<Vec3>& dirs,
                       std::vector<Eigen::Isometry3d>& poses, SimulatedLog& out) {
  const ScanSimOptions& o = w.o;
  const ScannerModel& sc = o.scanner;
  const bool vertical = k == 0;
  LaserScan scan;
  scan.t_start_s = t0 + i * sc.period_s + (vertical ? 0.0 : o.horizontal_time_offset_s);
  scan.duration_s = sc.sweepDurationS();
  scan.angle_min_rad = sc.angleMinRad();
  scan.angle_step_rad = sc.angleStepRad();
  scan.ranges_m.assign(static_cast<std::size_t>(w.beams), 0.0f);
  std::seed_seq noise_seed{o.seed, static_cast<std::uint32_t>(s), 2u, static_cast<std::uint32_t>(k),
                           static_cast<std::uint32_t>(i)};
  std::mt19937 noise_rng(noise_seed);
  const Eigen::Isometry3d start_pose = motion.pose(scan.t_start_s);
  poses.push_back(start_pose);
  Eigen::Isometry3d body = start_pose;
  for (int b = 0; b < w.beams; ++b) {
    const double noise = sc.range_noise_m * w.gauss(noise_rng);  // one draw per beam, always
    if (o.deskew && b > 0) body = motion.pose(scan.beamTime(static_cast<std::size_t>(b)));
    const Vec3 from =
        out.origin_m + body * w.mounts[k].translation();  // the world is in scenario coordinates
    const Vec3 d = body.linear() * dirs[static_cast<std::size_t>(b)];
    const double r = w.caster.cast(from, d, sc.max_range_m);
    ++out.rays;
    if (r < sc.min_range_m || r > sc.max_range_m) continue;
    const double rho = r + noise;
    if (rho < sc.min_range_m || rho > sc.max_range_m) continue;
    scan.ranges_m[static_cast<std::size_t>(b)] = static_cast<float>(rho);
    ++out.returns;
  }
  return scan;
}

/// Every scan of scanner k (0 vertical, 1 horizontal) of station s starting at t0.
void simulateScanner(Sweep& w, std::size_t s, int k, double t0, const StationMotion& motion,
                     Station& st, RawLogTruth::StationTruth& truth, SimulatedLog& out) {
  const ScannerModel& sc = w.o.scanner;
  const bool vertical = k == 0;
  auto& list = vertical ? st.vertical : st.horizontal;
  auto& poses = vertical ? truth.vertical_poses : truth.horizontal_poses;
  list.reserve(static_cast<std::size_t>(w.scans));
  // Beam directions in the body frame (the mount rotation applied once).
  std::vector<Vec3> dirs(static_cast<std::size_t>(w.beams));
  for (int b = 0; b < w.beams; ++b) {
    dirs[static_cast<std::size_t>(b)] =
        w.mounts[k].linear() * beamDir(vertical, sc.angleMinRad() + b * sc.angleStepRad());
  }
  for (int i = 0; i < w.scans; ++i)
    list.push_back(simulateScan(w, s, k, i, t0, motion, dirs, poses, out));
}

/// IMU of station s: from the first scan start (t0) to past the last beam, one
/// sample every 1/rate.
void simulateImu(Sweep& w, std::size_t s, double t0, const StationMotion& motion,
                 std::vector<ImuSample>& imu) {
  const ScanSimOptions& o = w.o;
  std::seed_seq imu_seed{o.seed, static_cast<std::uint32_t>(s), 3u};
  std::mt19937 imu_rng(imu_seed);
  auto& gauss = w.gauss;
  const double dt = 1.0 / o.imu_rate_hz;
  const int samples = static_cast<int>(std::ceil(w.span_s / dt)) + 2;
  imu.reserve(static_cast<std::size_t>(samples));
  for (int j = 0; j < samples; ++j) {
    ImuSample m;
    m.t_s = t0 + j * dt;
    Vec3 axis = drawVec3(gauss, imu_rng);
    if (axis.norm() < 1e-12) axis = Vec3::UnitZ();
    const double angle = o.imu_error_deg * kDeg * w.unit(imu_rng);
    const Eigen::Quaterniond q_true(motion.pose(m.t_s).linear());
    m.world_q_body =
        (q_true * Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()))).normalized();
    imu.push_back(m);
  }
}

/// Station s of the sweep: its motion, recorded pose, both scanners and the IMU.
void simulateStation(Sweep& w, std::size_t s, SimulatedLog& out) {
  const ScanSimOptions& o = w.o;
  const int sid = static_cast<int>(s);
  const double t0 = static_cast<double>(s) * w.station_s;
  const Vec3 position = o.stations[s] - out.origin_m;
  std::seed_seq motion_seed{o.seed, static_cast<std::uint32_t>(s), 0u};
  std::mt19937 motion_rng(motion_seed);
  const StationMotion motion(o, position, t0, w.span_s, motion_rng);

  Station st;
  st.id = sid;
  RawLogTruth::StationTruth truth;
  truth.id = sid;
  recordStation(w, s, position, st);
  // Scans: vertical (k = 0) and horizontal (k = 1).
  for (int k = 0; k < 2; ++k) simulateScanner(w, s, k, t0, motion, st, truth, out);
  simulateImu(w, s, t0, motion, st.imu);
  out.log.stations.push_back(std::move(st));
  out.truth.stations.push_back(std::move(truth));
}

}  // namespace

SimulatedLog simulateScans(const WorldModel& world, const ScanSimOptions& o,
                           const SimProgress& progress) {
  o.validate();
  // Every range is held as a float until the log is written.
  const double readings =
      static_cast<double>(o.stations.size()) * o.scansPerStation() * 2.0 * o.scanner.beamCount();
  requireMemory(readings * sizeof(float),
                "simulating " + formatNumber(readings / 1e6, 3) + " M range readings",
                "use fewer stations, a smaller turn_deg or a faster yaw_rate_deg_s");
  const RayCaster caster(world, o.thin_radius_m);
  const ScannerModel& sc = o.scanner;
  Sweep w(o, caster);
  SimulatedLog out;
  out.origin_m = o.stations.front();
  out.log.body_T_vertical = w.mounts[0];
  out.log.body_T_horizontal = w.mounts[1];
  out.log.max_range_m = sc.max_range_m;
  out.log.min_range_m = sc.min_range_m;
  for (std::size_t s = 0; s < o.stations.size(); ++s) {
    if (progress) {
      progress("simulating station " + std::to_string(s + 1) + "/" +
               std::to_string(o.stations.size()) + ": " + std::to_string(w.scans) +
               " scans x 2 scanners x " + std::to_string(w.beams) + " beams");
    }
    simulateStation(w, s, out);
  }
  return out;
}

}  // namespace uavip::sim
