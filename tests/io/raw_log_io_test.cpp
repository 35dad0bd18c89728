// Tests of io/raw_log_io: round trip of a simulated raw log and its truth, and a
// one-line error naming file and line for each kind of bad raw data.
#include "uavip/io/raw_log_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "uavip/core/error.h"
#include "uavip/sim/scanner_sim.h"

namespace uavip::io {
namespace {

namespace fs = std::filesystem;

sim::WorldModel room() {
  sim::WorldModel w;
  w.addBox("wall", Vec3(-4, -4, 0), Vec3(-3.5, 4, 3));
  w.addBox("pier", Vec3(2, -1, 0), Vec3(3, 1, 3));
  sim::Rect ground;
  ground.name = "ground";
  ground.corner = Vec3(-10, -10, 0);
  ground.edge_u = Vec3(20, 0, 0);
  ground.edge_v = Vec3(0, 20, 0);
  w.addPlane(ground);
  w.addLine("pole", Vec3(1, 3, 0), Vec3(1, 3, 2));
  w.addPoint("p", Vec3(-1, -2, 1));
  return w;
}

/// A single station, 5 scans per scanner.
sim::SimulatedLog smallLog() {
  sim::ScanSimOptions o;
  o.stations = {Vec3(0.5, 0.2, 1.5)};
  o.turn_deg = 3.0;
  o.imu_rate_hz = 400.0;
  return sim::simulateScans(room(), o);
}

class RawLogIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("uavip_rawlog_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    sim_ = smallLog();
    writeRawLog(dir_.string(), sim_.log);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string file(const std::string& name) const { return (dir_ / name).string(); }

  std::vector<std::string> lines(const std::string& name) const {
    std::ifstream in(file(name));
    std::vector<std::string> out;
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
  }
  void writeLines(const std::string& name, const std::vector<std::string>& ls,
                  bool final_newline = true) const {
    std::ofstream out(file(name), std::ios::trunc);
    for (std::size_t i = 0; i < ls.size(); ++i)
      out << ls[i] << (i + 1 < ls.size() || final_newline ? "\n" : "");
  }

  /// Reading fails with one line "<file>:<line>: ..." containing every fragment.
  void expectError(const std::string& name, std::size_t line,
                   const std::vector<std::string>& fragments) const {
    try {
      readRawLog(dir_.string());
      ADD_FAILURE() << "expected an error for " << name;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
      const std::string where = file(name) + ":" + std::to_string(line) + ": ";
      EXPECT_EQ(msg.rfind(where, 0), 0u) << "'" << where << "' does not start: " << msg;
      for (const auto& f : fragments)
        EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
    }
  }

  fs::path dir_;
  sim::SimulatedLog sim_;
};

TEST_F(RawLogIo, RoundTrip) {
  RawLogReadStats stats;
  const RawLog back = readRawLog(dir_.string(), &stats);
  const RawLog& log = sim_.log;
  EXPECT_DOUBLE_EQ(back.max_range_m, log.max_range_m);
  EXPECT_DOUBLE_EQ(back.min_range_m, log.min_range_m);
  EXPECT_TRUE(back.body_T_vertical.isApprox(log.body_T_vertical, 1e-8));
  EXPECT_TRUE(back.body_T_horizontal.isApprox(log.body_T_horizontal, 1e-8));
  ASSERT_EQ(back.stations.size(), 1u);
  const Station& a = log.stations[0];
  const Station& b = back.stations[0];
  EXPECT_EQ(b.id, a.id);
  EXPECT_TRUE(b.recorded_position.isApprox(a.recorded_position));
  EXPECT_DOUBLE_EQ(b.recorded_yaw_rad, a.recorded_yaw_rad);
  ASSERT_EQ(a.vertical.size(), 5u);
  ASSERT_EQ(b.vertical.size(), a.vertical.size());
  ASSERT_EQ(b.horizontal.size(), a.horizontal.size());
  std::size_t beams = 0, zeros = 0;
  for (const bool vertical : {true, false}) {
    const auto& sa = vertical ? a.vertical : a.horizontal;
    const auto& sb = vertical ? b.vertical : b.horizontal;
    for (std::size_t i = 0; i < sa.size(); ++i) {
      EXPECT_NEAR(sb[i].t_start_s, sa[i].t_start_s, 1e-6);
      EXPECT_NEAR(sb[i].duration_s, sa[i].duration_s, 1e-6);
      EXPECT_NEAR(sb[i].angle_min_rad, sa[i].angle_min_rad, 1e-9);
      EXPECT_NEAR(sb[i].angle_step_rad, sa[i].angle_step_rad, 1e-9);
      ASSERT_EQ(sb[i].ranges_m.size(), sa[i].ranges_m.size());
      for (std::size_t k = 0; k < sa[i].ranges_m.size(); ++k) {
        EXPECT_NEAR(sb[i].ranges_m[k], sa[i].ranges_m[k], 0.0005 + 1e-6);  // written in mm
        if (sa[i].ranges_m[k] == 0.0f) {
          EXPECT_EQ(sb[i].ranges_m[k], 0.0f);
          ++zeros;
        }
        ++beams;
      }
    }
  }
  ASSERT_EQ(b.imu.size(), a.imu.size());
  for (std::size_t i = 0; i < a.imu.size(); ++i) {
    EXPECT_NEAR(b.imu[i].t_s, a.imu[i].t_s, 1e-6);
    EXPECT_LT(b.imu[i].world_q_body.angularDistance(a.imu[i].world_q_body), 1e-8);
  }
  EXPECT_EQ(stats.scans, 10u);
  EXPECT_EQ(stats.beams, beams);
  EXPECT_EQ(stats.no_return, zeros);
  EXPECT_EQ(stats.replaced_ranges, 0u);
  EXPECT_EQ(stats.imu_samples, a.imu.size());
}

TEST_F(RawLogIo, TruthRoundTripIsInTheLogFrame) {
  EXPECT_FALSE(readRawLogTruth(dir_.string()).has_value());  // absent until written
  const sim::WorldModel world = room();
  writeRawLogTruth(dir_.string(), sim_.truth, world, sim_.origin_m, "room.yaml");
  const auto t = readRawLogTruth(dir_.string());
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(t->scenario, "room.yaml");
  EXPECT_TRUE(t->origin_m.isApprox(Vec3(0.5, 0.2, 1.5)));
  ASSERT_EQ(t->poses.stations.size(), 1u);
  ASSERT_EQ(t->poses.stations[0].vertical_poses.size(),
            sim_.truth.stations[0].vertical_poses.size());
  for (std::size_t i = 0; i < sim_.truth.stations[0].horizontal_poses.size(); ++i) {
    EXPECT_TRUE(t->poses.stations[0].horizontal_poses[i].isApprox(
        sim_.truth.stations[0].horizontal_poses[i], 1e-12));
  }
  ASSERT_EQ(t->world.rects().size(), world.rects().size());
  ASSERT_EQ(t->world.segments().size(), 1u);
  ASSERT_EQ(t->world.points().size(), 1u);
  // A scenario point p is at p − origin in the log frame.
  const Vec3 p(-3.5, 0.0, 1.0);  // on the wall's +x face
  EXPECT_NEAR(t->world.distanceToTruth(p - sim_.origin_m), 0.0, 1e-12);
  EXPECT_NEAR(t->world.distanceToTruth(Vec3(1, 3, 1) - sim_.origin_m), 0.0, 1e-12);  // on the pole
}

TEST_F(RawLogIo, TruncatedLastLine) {
  auto ls = lines("station_0_vertical.csv");
  const std::size_t last = ls.size();
  ls.back() = ls.back().substr(0, ls.back().size() / 2);
  writeLines("station_0_vertical.csv", ls, false);
  expectError("station_0_vertical.csv", last, {"truncated"});
}

TEST_F(RawLogIo, LineWithTooFewRanges) {
  auto ls = lines("station_0_horizontal.csv");
  ls[2] = ls[2].substr(
      0, ls[2].rfind(',', ls[2].size() / 2));  // cut at a comma: whole numbers, too few
  writeLines("station_0_horizontal.csv", ls);
  expectError("station_0_horizontal.csv", 3, {"truncated", "expected 1081 ranges"});
}

TEST_F(RawLogIo, ImuGapLongerThanAScan) {
  auto ls = lines("station_0_imu.csv");
  // Samples every 2.5 ms; drop 12 (30 ms > the 25 ms scan period) after line 20.
  ls.erase(ls.begin() + 20, ls.begin() + 32);
  writeLines("station_0_imu.csv", ls);
  expectError("station_0_imu.csv", 21, {"IMU gap", "longer than a scan period"});
}

TEST_F(RawLogIo, ShortImuGapIsFine) {
  auto ls = lines("station_0_imu.csv");
  ls.erase(ls.begin() + 20, ls.begin() + 25);  // 15 ms gap
  writeLines("station_0_imu.csv", ls);
  EXPECT_NO_THROW(readRawLog(dir_.string()));
}

TEST_F(RawLogIo, ImuEndingBeforeTheScans) {
  auto ls = lines("station_0_imu.csv");
  ls.resize(ls.size() / 2);
  writeLines("station_0_imu.csv", ls);
  expectError("station_0_imu.csv", ls.size(), {"IMU gap", "last sample"});
}

TEST_F(RawLogIo, ZeroAndOutOfRangeRangesAreNoReturns) {
  auto ls = lines("station_0_vertical.csv");
  // Line 2 (first scan): replace its first four ranges by 0, 45 (> 30 m max), −1 and 0.05 (< min).
  std::vector<std::string> f;
  std::stringstream ss(ls[1]);
  for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
  f[5] = "0";
  f[6] = "45.000";
  f[7] = "-1";
  f[8] = "0.05";
  f[9] = "12.5";
  std::string joined;
  for (std::size_t i = 0; i < f.size(); ++i) joined += (i ? "," : "") + f[i];
  ls[1] = joined;
  writeLines("station_0_vertical.csv", ls);
  RawLogReadStats stats;
  const RawLog log = readRawLog(dir_.string(), &stats);
  const auto& r = log.stations[0].vertical[0].ranges_m;
  EXPECT_EQ(r[0], 0.0f);
  EXPECT_EQ(r[1], 0.0f);
  EXPECT_EQ(r[2], 0.0f);
  EXPECT_EQ(r[3], 0.0f);
  EXPECT_FLOAT_EQ(r[4], 12.5f);
  EXPECT_EQ(stats.replaced_ranges, 3u);  // 45, −1 and 0.05; a 0 is already a no-return
}

TEST_F(RawLogIo, StationWithNoScans) {
  auto ls = lines("station_0_horizontal.csv");
  ls.resize(1);  // the header comment only
  writeLines("station_0_horizontal.csv", ls);
  expectError("station_0_horizontal.csv", 2, {"no scans"});
}

TEST_F(RawLogIo, ScanTimestampsGoingBackwards) {
  auto ls = lines("station_0_vertical.csv");
  std::swap(ls[2], ls[3]);  // scans 1 and 2
  writeLines("station_0_vertical.csv", ls);
  expectError("station_0_vertical.csv", 4, {"timestamps go backwards"});
}

TEST_F(RawLogIo, ImuTimestampsGoingBackwards) {
  auto ls = lines("station_0_imu.csv");
  std::swap(ls[5], ls[6]);
  writeLines("station_0_imu.csv", ls);
  expectError("station_0_imu.csv", 7, {"timestamps go backwards"});
}

TEST_F(RawLogIo, NotANumber) {
  auto ls = lines("station_0_vertical.csv");
  ls[1].replace(ls[1].find(','), 1, "x,");
  writeLines("station_0_vertical.csv", ls);
  expectError("station_0_vertical.csv", 2, {"t_start_s must be a number"});
}

TEST_F(RawLogIo, TruncatedIndex) {
  auto ls = lines("log.json");
  ls.resize(ls.size() / 2);
  writeLines("log.json", ls);
  expectError("log.json", ls.size() + 1, {"not valid JSON"});
}

TEST_F(RawLogIo, MaxRangeBeyondAFloatIsRefused) {
  // max_range_m 1e300 let a range of 1e299 through, which overflowed to infinity when
  // stored as float (found while checking a fuzz report).
  auto ls = lines("log.json");
  for (auto& l : ls)
    l = std::regex_replace(l, std::regex("\"max_range_m\": [0-9.e+]+"), "\"max_range_m\": 1e300");
  writeLines("log.json", ls);
  try {
    readRawLog(dir_.string());
    FAIL() << "max_range_m 1e300 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_range_m must be <= 10000 m"), std::string::npos)
        << e.what();
  }
}

TEST_F(RawLogIo, MissingStationFile) {
  fs::remove(file("station_0_imu.csv"));
  try {
    readRawLog(dir_.string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("station_0_imu.csv"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace uavip::io
