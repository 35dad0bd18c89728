// Meshes in: how long reading (Assimp) and sampling a mesh take, and how close a
// planned flight comes to the mesh's triangles.
//
//   uavip_mesh_bench MESH [--spacing S] [--runs R] [--mission MISSION.json [--offset X Y Z]]
//
// Prints the median of R runs of io::readMesh and io::sampleMesh (and the points per
// second of each), then, with --mission, the exact distance from every sortie's
// waypoint polyline (sampled every 5 cm) to every triangle within 2 m of it (a 1 m
// grid over the triangles' boxes; the point-triangle distance in closed form), which
// is the flight's clearance to the mesh itself, not to the points sampled from it.
// --offset is added to the mission's coordinates (a recentred scene's source_offset_m).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <vector>

#include "bench_util.h"
#include "uavip/core/stopwatch.h"
#include "uavip/io/mesh_reader.h"

namespace {

using uavip::Vec3;

/// Exact distance from p to the triangle (a, b, c) (Ericson, Real-Time Collision
/// Detection, 5.1.5).
double pointTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double denom = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

using Cell = std::tuple<long, long, long>;
Cell cellOf(const Vec3& p) {
  return {static_cast<long>(std::floor(p.x())), static_cast<long>(std::floor(p.y())),
          static_cast<long>(std::floor(p.z()))};
}

/// The flight's smallest distance to the triangles (beyond 2 m: reported as infinity).
double flightToMesh(const uavip::io::TriangleMesh& mesh, const std::string& mission,
                    const Vec3& offset, std::size_t* samples) {
  std::map<Cell, std::vector<std::size_t>> grid;  // 1 m cells
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    Vec3 lo = mesh.vertices[t[0]], hi = lo;
    for (const auto v : t) {
      lo = lo.cwiseMin(mesh.vertices[v]);
      hi = hi.cwiseMax(mesh.vertices[v]);
    }
    const Cell a = cellOf(lo), b = cellOf(hi);
    for (long x = std::get<0>(a); x <= std::get<0>(b); ++x)
      for (long y = std::get<1>(a); y <= std::get<1>(b); ++y)
        for (long z = std::get<2>(a); z <= std::get<2>(b); ++z) grid[{x, y, z}].push_back(i);
  }
  std::ifstream in(mission);
  const nlohmann::json m = nlohmann::json::parse(in);
  double best = HUGE_VAL;
  const auto at = [&](const Vec3& q) {
    ++*samples;
    const Cell c = cellOf(q);
    for (long dx = -2; dx <= 2; ++dx)
      for (long dy = -2; dy <= 2; ++dy)
        for (long dz = -2; dz <= 2; ++dz) {
          const auto it =
              grid.find({std::get<0>(c) + dx, std::get<1>(c) + dy, std::get<2>(c) + dz});
          if (it == grid.end()) continue;
          for (const std::size_t i : it->second) {
            const auto& t = mesh.triangles[i];
            best = std::min(best, pointTriangle(q, mesh.vertices[t[0]], mesh.vertices[t[1]],
                                                mesh.vertices[t[2]]));
          }
        }
  };
  for (const auto& sortie : m.at("flight").at("sorties")) {
    std::vector<Vec3> w;
    for (const auto& p : sortie.at("waypoints"))
      w.emplace_back(Vec3(p[0].get<double>(), p[1].get<double>(), p[2].get<double>()) + offset);
    for (std::size_t k = 0; k + 1 < w.size(); ++k) {
      const int steps = std::max(1, static_cast<int>(std::ceil((w[k + 1] - w[k]).norm() / 0.05)));
      for (int s = 0; s <= steps; ++s)
        at(w[k] + (w[k + 1] - w[k]) * (static_cast<double>(s) / steps));
    }
  }
  return best <= 2.0 ? best : HUGE_VAL;
}

}  // namespace

int main(int argc, char** argv) try {
  uavip::bench_util::prepareProcess();
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: uavip_mesh_bench MESH [--spacing S] [--runs R] [--mission M.json "
                 "[--offset X Y Z]]\n");
    return 2;
  }
  const std::string path = argv[1];
  uavip::io::MeshSampleOptions options;
  int runs = 3;
  std::string mission;
  Vec3 offset = Vec3::Zero();
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--spacing" && i + 1 < argc) options.spacing_m = std::atof(argv[++i]);
    if (a == "--runs" && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
    if (a == "--mission" && i + 1 < argc) mission = argv[++i];
    if (a == "--offset" && i + 3 < argc) {
      for (int k = 0; k < 3; ++k) offset[k] = std::atof(argv[++i]);
    }
  }
  std::vector<double> read_s, sample_s;
  uavip::io::TriangleMesh mesh;
  uavip::io::MeshReadInfo info;
  std::size_t points = 0;
  for (int r = 0; r < runs; ++r) {
    auto t0 = uavip::SteadyClock::now();
    mesh = uavip::io::readMesh(path, 1.0, &info);
    read_s.push_back(uavip::secondsSince(t0));
    t0 = uavip::SteadyClock::now();
    points = uavip::io::sampleMesh(mesh, options, path, &info).size();
    sample_s.push_back(uavip::secondsSince(t0));
  }
  const double read = uavip::bench_util::median(read_s),
               sample = uavip::bench_util::median(sample_s);
  std::printf("%s: %zu triangles, %.1f m2, spacing %.4f m (%s), %zu points\n", path.c_str(),
              info.triangles, info.area_m2, info.spacing_m, info.spacing_source.c_str(), points);
  std::printf(
      "read (Assimp) %.3f s (%.2f M triangles/s), sample %.3f s (%.2f M points/s), "
      "median of %d; peak RSS %.0f MiB\n",
      read, info.triangles / read / 1e6, sample, points / sample / 1e6, runs,
      uavip::bench_util::peakRssMiB());
  if (!mission.empty()) {
    std::size_t samples = 0;
    const double d = flightToMesh(mesh, mission, offset, &samples);
    std::printf("flight to mesh triangles: min distance %s over %zu path samples (every 5 cm)\n",
                std::isfinite(d) ? (std::to_string(d).substr(0, 5) + " m").c_str() : "beyond 2 m",
                samples);
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "uavip_mesh_bench: %s\n", e.what());
  return 2;
}
