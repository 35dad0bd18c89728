#include "uavip/io/raw_log_io.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <system_error>

#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/json_reader.h"

namespace uavip::io {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kFormat = "uavip-raw-log";
constexpr int kVersion = 1;
/// A read quaternion must have a norm within this of 1 (written with 9 decimals).
constexpr double kQuatNormTol = 1e-3;

// ------------------------------------------------------------------ writing

/// Appends v in fixed notation with `digits` decimals (locale-free).
void appendFixed(std::string& out, double v, int digits) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::fixed, digits);
  out.append(buf, res.ptr);
}

/// A range in millimetres, "0" for a no-return.
void appendRange(std::string& out, float r) {
  if (r == 0.0f) {
    out += '0';
    return;
  }
  appendFixed(out, static_cast<double>(r), 3);
}

std::string scanCsv(const std::vector<LaserScan>& scans, const std::string& what) {
  std::string out =
      "# uavip raw log, " + what +
      " scans: t_start_s,duration_s,angle_min_rad,angle_step_rad,beam_count,range_0_m,...,"
      "range_{beam_count-1}_m (0 = no return)\n";
  out.reserve(out.size() +
              scans.size() * (60 + 7 * (scans.empty() ? 0 : scans.front().ranges_m.size())));
  for (const auto& s : scans) {
    require(std::isfinite(s.t_start_s) && std::isfinite(s.duration_s) &&
                std::isfinite(s.angle_min_rad) && std::isfinite(s.angle_step_rad),
            "raw log", "scan times and angles must be finite");
    appendFixed(out, s.t_start_s, 6);
    out += ',';
    appendFixed(out, s.duration_s, 6);
    out += ',';
    appendFixed(out, s.angle_min_rad, 9);
    out += ',';
    appendFixed(out, s.angle_step_rad, 9);
    out += ',';
    out += std::to_string(s.ranges_m.size());
    for (const float r : s.ranges_m) {
      out += ',';
      appendRange(out, std::isfinite(r) ? r : 0.0f);
    }
    out += '\n';
  }
  return out;
}

std::string imuCsv(const std::vector<ImuSample>& imu) {
  std::string out =
      "# uavip raw log, IMU samples: t_s,qw,qx,qy,qz (world_q_body, unit quaternion)\n";
  out.reserve(out.size() + imu.size() * 64);
  for (const auto& m : imu) {
    const Eigen::Quaterniond q = m.world_q_body.normalized();
    require(std::isfinite(m.t_s) && q.coeffs().allFinite(), "raw log",
            "IMU samples must be finite");
    appendFixed(out, m.t_s, 6);
    for (const double c : {q.w(), q.x(), q.y(), q.z()}) {
      out += ',';
      appendFixed(out, c, 9);
    }
    out += '\n';
  }
  return out;
}

json vecJson(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

json mountJson(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.rotation());
  return {{"translation_m", vecJson(T.translation())},
          {"rotation_wxyz", {q.w(), q.x(), q.y(), q.z()}}};
}

json poseJson(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.rotation());
  const Vec3 t = T.translation();
  return json::array({t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z()});
}

// ------------------------------------------------------------------ reading

[[noreturn]] void failAt(const std::string& file, std::size_t line, const std::string& what) {
  throw InputError(file + ":" + std::to_string(line) + ": " + what);
}

/// Line-by-line reader over a whole file with 1-based line numbers; comment lines
/// ('#') and empty lines are skipped. Every line must end with '\n' (a missing one
/// means the file was cut).
class LineReader {
 public:
  LineReader(std::string path, std::string text) : path_(std::move(path)), text_(std::move(text)) {}

  /// Next data line (without '\n'); false at the end.
  bool next(std::string_view& line) {
    while (pos_ < text_.size()) {
      ++line_no_;
      const std::size_t end = text_.find('\n', pos_);
      if (end == std::string::npos) {
        fail("truncated: the last line has no end of line (the file was cut)");
      }
      std::string_view l(text_.data() + pos_, end - pos_);
      pos_ = end + 1;
      if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
      if (l.empty() || l.front() == '#') continue;
      line = l;
      return true;
    }
    return false;
  }

  [[noreturn]] void fail(const std::string& what) const { failAt(path_, line_no_, what); }
  std::size_t lineNo() const { return line_no_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::string text_;
  std::size_t pos_{0};
  std::size_t line_no_{0};
};

/// Splits a CSV line into fields and parses them as numbers.
class Fields {
 public:
  Fields(std::string_view line, const LineReader& r) : line_(line), reader_(r) {}

  bool done() const { return pos_ > line_.size(); }

  /// Next field as a double; `name` is used in messages.
  double number(const std::string& name) {
    if (done()) reader_.fail("truncated: " + name + " is missing");
    std::size_t end = line_.find(',', pos_);
    if (end == std::string_view::npos) end = line_.size();
    std::string_view f = line_.substr(pos_, end - pos_);
    pos_ = end + 1;
    while (!f.empty() && f.front() == ' ') f.remove_prefix(1);
    while (!f.empty() && f.back() == ' ') f.remove_suffix(1);
    double v = 0.0;
    const char* first = f.data();
    if (!f.empty() && f.front() == '+') ++first;
    const auto res = std::from_chars(first, f.data() + f.size(), v);
    if (f.empty() || res.ec != std::errc() || res.ptr != f.data() + f.size()) {
      if (res.ec == std::errc::result_out_of_range) return std::numeric_limits<double>::infinity();
      reader_.fail(name + " must be a number, got '" + std::string(f) + "'");
    }
    return v;
  }

  double finite(const std::string& name) {
    const double v = number(name);
    if (!std::isfinite(v)) reader_.fail(name + " must be finite, got " + formatNumber(v, 9));
    return v;
  }

 private:
  std::string_view line_;
  const LineReader& reader_;
  std::size_t pos_{0};
};

/// Largest max_range_m a log may declare [m].
constexpr double kMaxRangeM = 10000.0;

std::string readText(const std::string& path) {
  if (!fs::exists(path))
    throw InputError(path + ": missing file of the raw log (see docs/raw_log_format.md)");
  return readFile(path);
}

/// Reads one scan file. Scans must have strictly increasing start times.
std::vector<LaserScan> readScans(const std::string& path, const RawLog& log,
                                 RawLogReadStats& stats) {
  LineReader r(path, readText(path));
  std::vector<LaserScan> scans;
  std::string_view line;
  while (r.next(line)) {
    Fields f(line, r);
    LaserScan s;
    s.t_start_s = f.finite("t_start_s");
    s.duration_s = f.finite("duration_s");
    if (s.duration_s < 0.0) r.fail("duration_s must be >= 0, got " + formatNumber(s.duration_s, 9));
    s.angle_min_rad = f.finite("angle_min_rad");
    s.angle_step_rad = f.finite("angle_step_rad");
    const double n = f.finite("beam_count");
    if (n < 1.0 || n > 100000.0 || n != std::floor(n)) {
      r.fail("beam_count must be a whole number in [1, 100000], got " + formatNumber(n, 9));
    }
    const auto count = static_cast<std::size_t>(n);
    s.ranges_m.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
      if (f.done()) {
        r.fail("truncated: expected " + std::to_string(count) + " ranges, got " +
               std::to_string(i));
      }
      const double v = f.number("range " + std::to_string(i));
      const bool valid = std::isfinite(v) && v >= log.min_range_m && v <= log.max_range_m;
      if (!valid && v != 0.0) ++stats.replaced_ranges;
      if (!valid) ++stats.no_return;
      s.ranges_m[i] = valid ? static_cast<float>(v) : 0.0f;
    }
    if (!f.done()) r.fail("more than beam_count = " + std::to_string(count) + " ranges");
    if (!scans.empty() && !(s.t_start_s > scans.back().t_start_s)) {
      r.fail("timestamps go backwards: t_start_s " + formatNumber(s.t_start_s, 9) +
             " is not after the previous scan's " + formatNumber(scans.back().t_start_s, 9));
    }
    stats.beams += count;
    ++stats.scans;
    scans.push_back(std::move(s));
  }
  if (scans.empty())
    failAt(path, r.lineNo() + 1, "no scans: a station needs at least one scan per scanner");
  return scans;
}

/// Reads one IMU file and checks it covers the scans without a gap longer than a scan period.
std::vector<ImuSample> readImu(const std::string& path, const Station& st, RawLogReadStats& stats) {
  LineReader r(path, readText(path));
  std::vector<ImuSample> imu;
  // The longest allowed gap: one scan period (median spacing of the vertical scans,
  // or a scan's duration when there is only one scan).
  double period = st.vertical.front().duration_s;
  for (const auto* list : {&st.vertical, &st.horizontal}) {
    if (list->size() >= 2) {
      std::vector<double> d;
      for (std::size_t i = 1; i < list->size(); ++i)
        d.push_back((*list)[i].t_start_s - (*list)[i - 1].t_start_s);
      std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
      period = d[d.size() / 2];
      break;
    }
  }
  period = std::max(period, 1e-6);
  const double first_scan =
      std::min(st.vertical.front().t_start_s, st.horizontal.front().t_start_s);
  const double last_scan =
      std::max(st.vertical.back().t_start_s + st.vertical.back().duration_s,
               st.horizontal.back().t_start_s + st.horizontal.back().duration_s);
  // Timestamps are written with 6 decimals: allow their rounding.
  const double allowed_gap = period + 2e-6;
  std::string_view line;
  while (r.next(line)) {
    Fields f(line, r);
    ImuSample m;
    m.t_s = f.finite("t_s");
    Eigen::Quaterniond q;
    q.w() = f.finite("qw");
    q.x() = f.finite("qx");
    q.y() = f.finite("qy");
    q.z() = f.finite("qz");
    if (!f.done()) r.fail("expected 5 fields (t_s,qw,qx,qy,qz), got more");
    if (std::abs(q.norm() - 1.0) > kQuatNormTol)
      r.fail("quaternion must have norm 1, got " + formatNumber(q.norm(), 9));
    m.world_q_body = q.normalized();
    if (imu.empty()) {
      if (m.t_s > first_scan + allowed_gap) {
        r.fail("IMU gap: the first sample at t = " + formatNumber(m.t_s, 9) +
               " s comes more than a scan period (" + formatNumber(period, 9) +
               " s) after the first scan at " + formatNumber(first_scan, 9) + " s");
      }
    } else {
      const double prev = imu.back().t_s;
      if (!(m.t_s > prev)) {
        r.fail("timestamps go backwards: t_s " + formatNumber(m.t_s, 9) +
               " is not after the previous sample's " + formatNumber(prev, 9));
      }
      if (m.t_s - prev > allowed_gap && m.t_s > first_scan && prev < last_scan) {
        r.fail("IMU gap of " + formatNumber(m.t_s - prev, 9) +
               " s after t = " + formatNumber(prev, 9) + " s is longer than a scan period (" +
               formatNumber(period, 9) + " s)");
      }
    }
    imu.push_back(m);
  }
  if (imu.empty())
    failAt(path, r.lineNo() + 1, "no IMU samples: a station needs IMU samples over its scans");
  if (imu.back().t_s < last_scan - allowed_gap) {
    failAt(path, r.lineNo(),
           "IMU gap: the last sample at t = " + formatNumber(imu.back().t_s, 9) +
               " s ends more than a scan period before the last scan ends at " +
               formatNumber(last_scan, 9) + " s");
  }
  stats.imu_samples += imu.size();
  return imu;
}

/// log.json access by key (`path` is the parent's field path with a trailing dot),
/// on the strict io::JsonReader, plus the log's rotations and poses.
class LogJson {
 public:
  explicit LogJson(std::string file) : r_(std::move(file)) {}

  json parse(const std::string& text) const { return r_.parse(text); }
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    r_.fail(key, what);
  }
  const json& get(const json& j, const std::string& key, const std::string& path) const {
    if (!j.is_object() || !j.contains(key)) fail(path + key, "is missing");
    return j.at(key);
  }
  double number(const json& j, const std::string& key, const std::string& path) const {
    return r_.number(get(j, key, path), path + key);
  }
  std::string text(const json& j, const std::string& key, const std::string& path) const {
    return r_.text(get(j, key, path), path + key);
  }
  Vec3 vec3(const json& j, const std::string& key, const std::string& path) const {
    return r_.vec3(get(j, key, path), path + key);
  }

  std::vector<double> numbers(const json& j, const std::string& key, const std::string& path,
                              std::size_t n) const {
    const json& v = get(j, key, path);
    if (!v.is_array() || v.size() != n)
      fail(path + key, "must be a list of " + std::to_string(n) + " numbers, got " + v.dump());
    std::vector<double> out;
    for (const auto& x : v) {
      if (!x.is_number() || !std::isfinite(x.get<double>()))
        fail(path + key, "must hold finite numbers, got " + v.dump());
      out.push_back(x.get<double>());
    }
    return out;
  }

  Eigen::Quaterniond quat(const json& j, const std::string& key, const std::string& path) const {
    const auto v = numbers(j, key, path, 4);
    const Eigen::Quaterniond q(v[0], v[1], v[2], v[3]);
    if (std::abs(q.norm() - 1.0) > kQuatNormTol)
      fail(path + key, "must be a unit quaternion, got norm " + formatNumber(q.norm(), 9));
    return q.normalized();
  }

  Eigen::Isometry3d pose7(const json& v, const std::string& path) const {
    if (!v.is_array() || v.size() != 7)
      fail(path, "must be [tx, ty, tz, qw, qx, qy, qz], got " + v.dump());
    double c[7];
    for (std::size_t i = 0; i < 7; ++i) {
      if (!v[i].is_number()) fail(path, "must hold numbers, got " + v.dump());
      c[i] = v[i].get<double>();
    }
    const Eigen::Quaterniond q(c[3], c[4], c[5], c[6]);
    if (!std::isfinite(q.norm()) || std::abs(q.norm() - 1.0) > kQuatNormTol)
      fail(path, "quaternion must have norm 1");
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.normalized().toRotationMatrix();
    T.translation() = Vec3(c[0], c[1], c[2]);
    return T;
  }

 private:
  JsonReader r_;
};

Eigen::Isometry3d readMount(const LogJson& jr, const json& j, const std::string& path) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = jr.quat(j, "rotation_wxyz", path).toRotationMatrix();
  T.translation() = jr.vec3(j, "translation_m", path);
  return T;
}

}  // namespace

std::string rawLogIndexName() { return "log.json"; }
std::string rawLogTruthName() { return "truth.json"; }
std::string rawLogScanFileName(int station_id, bool vertical) {
  return "station_" + std::to_string(station_id) + (vertical ? "_vertical.csv" : "_horizontal.csv");
}
std::string rawLogImuFileName(int station_id) {
  return "station_" + std::to_string(station_id) + "_imu.csv";
}

void writeRawLog(const std::string& dir, const RawLog& log) {
  require(std::isfinite(log.max_range_m) && std::isfinite(log.min_range_m) &&
              log.min_range_m >= 0.0 && log.min_range_m < log.max_range_m,
          "raw log", "min_range_m and max_range_m must satisfy 0 <= min < max");
  ensureDirectory(dir);
  StagedOutputs outputs;  // the log's files are written together
  json stations = json::array();
  std::set<int> ids;
  for (const Station& st : log.stations) {
    require(ids.insert(st.id).second, "raw log",
            "station ids must be unique, got " + std::to_string(st.id) + " twice");
    require(st.id >= 0, "raw log", "station ids must be >= 0, got " + std::to_string(st.id));
    require(st.recorded_position.allFinite() && std::isfinite(st.recorded_yaw_rad), "raw log",
            "station " + std::to_string(st.id) + " recorded position and yaw must be finite");
    outputs.write((fs::path(dir) / rawLogScanFileName(st.id, true)).string(),
                  scanCsv(st.vertical, "vertical"));
    outputs.write((fs::path(dir) / rawLogScanFileName(st.id, false)).string(),
                  scanCsv(st.horizontal, "horizontal"));
    outputs.write((fs::path(dir) / rawLogImuFileName(st.id)).string(), imuCsv(st.imu));
    stations.push_back({{"id", st.id},
                        {"recorded_position_m", vecJson(st.recorded_position)},
                        {"recorded_yaw_rad", st.recorded_yaw_rad},
                        {"vertical_scans", rawLogScanFileName(st.id, true)},
                        {"horizontal_scans", rawLogScanFileName(st.id, false)},
                        {"imu", rawLogImuFileName(st.id)}});
  }
  const json index = {
      {"format", kFormat},
      {"version", kVersion},
      {"description",
       "Two 2D laser scanners and an IMU, yawing 360 deg per station (docs/raw_log_format.md). "
       "World frame: "
       "ENU, origin at the UAV centre at the first scan of station 0. Vertical beam: x*=-r cos a, "
       "y*=0, "
       "z*=-r sin a; horizontal beam: x*=r cos a, y*=r sin a, z*=0; x = body_T_scanner * x*."},
      {"max_range_m", log.max_range_m},
      {"min_range_m", log.min_range_m},
      {"mounts",
       {{"vertical", mountJson(log.body_T_vertical)},
        {"horizontal", mountJson(log.body_T_horizontal)}}},
      {"stations", stations}};
  outputs.write((fs::path(dir) / rawLogIndexName()).string(), index.dump(1) + "\n");
  outputs.commit();
}

void writeRawLogTruth(const std::string& dir, const RawLogTruth& truth,
                      const sim::WorldModel& world, const Vec3& origin_m,
                      const std::string& scenario) {
  ensureDirectory(dir);
  json stations = json::array();
  for (const auto& st : truth.stations) {
    json v = json::array(), h = json::array();
    for (const auto& T : st.vertical_poses) v.push_back(poseJson(T));
    for (const auto& T : st.horizontal_poses) h.push_back(poseJson(T));
    stations.push_back({{"id", st.id}, {"vertical_poses", v}, {"horizontal_poses", h}});
  }
  json rects = json::array(), segments = json::array(), points = json::array();
  for (const auto& r : world.rects()) {
    rects.push_back({{"name", r.name},
                     {"corner", vecJson(r.corner - origin_m)},
                     {"edge_u", vecJson(r.edge_u)},
                     {"edge_v", vecJson(r.edge_v)}});
  }
  for (const auto& s : world.segments()) {
    segments.push_back(
        {{"name", s.name}, {"a", vecJson(s.a - origin_m)}, {"b", vecJson(s.b - origin_m)}});
  }
  for (const auto& p : world.points())
    points.push_back({{"name", p.name}, {"p", vecJson(p.p - origin_m)}});
  const json j = {{"format", "uavip-raw-log-truth"},
                  {"version", kVersion},
                  {"description",
                   "Ground truth of a simulated raw log, in the log frame (scenario coordinates "
                   "minus origin_m). "
                   "Poses: world_T_body at each scan start as [tx, ty, tz, qw, qx, qy, qz]. Read "
                   "only to score."},
                  {"scenario", scenario},
                  {"origin_m", vecJson(origin_m)},
                  {"stations", stations},
                  {"world", {{"rects", rects}, {"segments", segments}, {"points", points}}}};
  writeFileAtomic((fs::path(dir) / rawLogTruthName()).string(), j.dump() + "\n");
}

RawLogReader::RawLogReader(const std::string& dir) {
  const std::string index_path = (fs::path(dir) / rawLogIndexName()).string();
  if (!fs::is_directory(dir))
    throw InputError(dir + ": not a raw log directory (expected " + index_path + ")");
  const LogJson jr(index_path);
  const json j = jr.parse(readText(index_path));
  if (!j.is_object()) jr.fail("top level", "must be a JSON object");
  if (jr.text(j, "format", "") != kFormat)
    jr.fail("format", std::string("must be '") + kFormat + "'");
  if (jr.number(j, "version", "") != kVersion) {
    jr.fail("version", "must be " + std::to_string(kVersion) + ", got " + j.at("version").dump());
  }
  RawLog& log = header_;
  log.max_range_m = jr.number(j, "max_range_m", "");
  log.min_range_m = jr.number(j, "min_range_m", "");
  if (!(log.max_range_m <=
        kMaxRangeM))  // ranges are stored as float: a larger bound lets them overflow
    jr.fail("max_range_m", "must be <= " + formatNumber(kMaxRangeM) +
                               " m (a laser scanner's reach), got " +
                               formatNumber(log.max_range_m, 9));
  if (!(log.min_range_m >= 0.0 && log.min_range_m < log.max_range_m)) {
    jr.fail("min_range_m", "must be >= 0 and < max_range_m, got " +
                               formatNumber(log.min_range_m, 9) + " and " +
                               formatNumber(log.max_range_m, 9));
  }
  const json& mounts = jr.get(j, "mounts", "");
  log.body_T_vertical = readMount(jr, jr.get(mounts, "vertical", "mounts."), "mounts.vertical.");
  log.body_T_horizontal =
      readMount(jr, jr.get(mounts, "horizontal", "mounts."), "mounts.horizontal.");
  const json& stations = jr.get(j, "stations", "");
  if (!stations.is_array() || stations.empty())
    jr.fail("stations", "must be a non-empty list of station records");
  std::set<int> ids;
  for (std::size_t i = 0; i < stations.size(); ++i) {
    const std::string path = "stations[" + std::to_string(i) + "].";
    const json& sj = stations[i];
    Station st;
    const double id = jr.number(sj, "id", path);
    if (id < 0 || id > 1e6 || id != std::floor(id))
      jr.fail(path + "id", "must be a whole number >= 0, got " + formatNumber(id, 9));
    st.id = static_cast<int>(id);
    if (!ids.insert(st.id).second)
      jr.fail(path + "id", "repeats station id " + std::to_string(st.id));
    st.recorded_position = jr.vec3(sj, "recorded_position_m", path);
    st.recorded_yaw_rad = jr.number(sj, "recorded_yaw_rad", path);
    auto file = [&](const std::string& key) {
      const std::string name = jr.text(sj, key, path);
      if (name.empty() || name.find('/') != std::string::npos ||
          name.find('\\') != std::string::npos) {
        jr.fail(path + key, "must be a file name inside the log directory, got '" + name + "'");
      }
      return (fs::path(dir) / name).string();
    };
    files_.push_back({file("vertical_scans"), file("horizontal_scans"), file("imu")});
    log.stations.push_back(std::move(st));
  }
}

std::uintmax_t RawLogReader::stationFileBytes(std::size_t i) const {
  std::uintmax_t bytes = 0;
  for (const std::string* f :
       {&files_.at(i).vertical, &files_.at(i).horizontal, &files_.at(i).imu}) {
    std::error_code ec;
    const std::uintmax_t n = fs::file_size(*f, ec);
    if (!ec) bytes += n;
  }
  return bytes;
}

Station RawLogReader::readStation(std::size_t i, RawLogReadStats& stats) const {
  Station st = header_.stations.at(i);
  st.vertical = readScans(files_[i].vertical, header_, stats);
  st.horizontal = readScans(files_[i].horizontal, header_, stats);
  st.imu = readImu(files_[i].imu, st, stats);
  return st;
}

RawLog readRawLog(const std::string& dir, RawLogReadStats* stats_out) {
  const RawLogReader reader(dir);
  RawLog log = reader.header();
  RawLogReadStats stats;
  for (std::size_t i = 0; i < reader.stationCount(); ++i)
    log.stations[i] = reader.readStation(i, stats);
  if (stats_out) *stats_out = stats;
  return log;
}

std::optional<RawLogTruthFile> readRawLogTruth(const std::string& dir) {
  const std::string path = (fs::path(dir) / rawLogTruthName()).string();
  if (!fs::exists(path)) return std::nullopt;
  const LogJson jr(path);
  const json j = jr.parse(readFile(path));
  if (!j.is_object()) jr.fail("top level", "must be a JSON object");
  if (jr.text(j, "format", "") != "uavip-raw-log-truth")
    jr.fail("format", "must be 'uavip-raw-log-truth'");
  RawLogTruthFile t;
  t.scenario =
      j.contains("scenario") && j["scenario"].is_string() ? j["scenario"].get<std::string>() : "";
  t.origin_m = jr.vec3(j, "origin_m", "");
  const json& stations = jr.get(j, "stations", "");
  if (!stations.is_array()) jr.fail("stations", "must be a list");
  for (std::size_t i = 0; i < stations.size(); ++i) {
    const std::string p = "stations[" + std::to_string(i) + "].";
    RawLogTruth::StationTruth st;
    st.id = static_cast<int>(jr.number(stations[i], "id", p));
    for (const char* key : {"vertical_poses", "horizontal_poses"}) {
      const json& list = jr.get(stations[i], key, p);
      if (!list.is_array()) jr.fail(p + key, "must be a list of poses");
      auto& out = std::string(key) == "vertical_poses" ? st.vertical_poses : st.horizontal_poses;
      for (std::size_t k = 0; k < list.size(); ++k)
        out.push_back(jr.pose7(list[k], p + key + "[" + std::to_string(k) + "]"));
    }
    t.poses.stations.push_back(std::move(st));
  }
  const json& world = jr.get(j, "world", "");
  try {
    for (const auto& r : jr.get(world, "rects", "world.")) {
      sim::Rect rect;
      rect.name = jr.text(r, "name", "world.rects[].");
      rect.corner = jr.vec3(r, "corner", "world.rects[].");
      rect.edge_u = jr.vec3(r, "edge_u", "world.rects[].");
      rect.edge_v = jr.vec3(r, "edge_v", "world.rects[].");
      t.world.addPlane(rect);
    }
    for (const auto& s : jr.get(world, "segments", "world.")) {
      t.world.addLine(jr.text(s, "name", "world.segments[]."), jr.vec3(s, "a", "world.segments[]."),
                      jr.vec3(s, "b", "world.segments[]."));
    }
    for (const auto& p : jr.get(world, "points", "world.")) {
      t.world.addPoint(jr.text(p, "name", "world.points[]."), jr.vec3(p, "p", "world.points[]."));
    }
  } catch (const InputError& e) {
    const std::string msg = e.what();
    if (msg.rfind(path, 0) == 0) throw;
    throw InputError(path + ": " + msg);
  }
  return t;
}

}  // namespace uavip::io
