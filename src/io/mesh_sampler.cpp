// A triangle mesh's surface as points (io/mesh_reader.h, sampleMesh): counts by
// area with a seeded fraction per triangle, R2 points folded onto each triangle; the
// triangles with area (the safety surface) and their binary STL copy.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <vector>

#include "cloud_formats.h"
#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/mesh_reader.h"

namespace uavip::io {
namespace {

/// SplitMix64's finaliser: a 64-bit hash whose outputs are uniform for distinct inputs.
std::uint64_t mix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// A uniform number in [0, 1) from (seed, triangle, stream) alone.
double uniform01(std::uint64_t seed, std::uint64_t triangle, std::uint64_t stream) {
  const std::uint64_t h = mix64(mix64(seed ^ mix64(triangle)) + stream);
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

/// The R2 sequence's steps, 1/g and 1/g² with g the plastic number (g³ = g + 1).
constexpr double kR2Step1 = 0.75487766624669276;
constexpr double kR2Step2 = 0.56984029099805327;

/// A triangle's corners; `area` 0 when degenerate (collinear corners, non-finite).
struct Corners {
  Vec3 a, b, c;
  double area{0.0};
};

Corners corners(const TriangleMesh& mesh, std::size_t i, const std::string& path) {
  const auto& t = mesh.triangles[i];
  for (const std::uint32_t v : t) {
    if (v >= mesh.vertices.size())
      throw InputError(path + ": triangle " + std::to_string(i) + " names vertex " +
                       std::to_string(v) + ", but the mesh has " +
                       std::to_string(mesh.vertices.size()) + " vertices; the file is corrupt");
  }
  Corners k{mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
  for (const Vec3* p : {&k.a, &k.b, &k.c}) {
    if (!p->allFinite())
      throw InputError(path + ": triangle " + std::to_string(i) + " has a non-finite vertex " +
                       formatRawPoint(*p) + "; the file is corrupt");
  }
  const Vec3 ab = k.b - k.a, ac = k.c - k.a;
  const double twice = ab.cross(ac).norm();
  const double longest = std::max({ab.squaredNorm(), ac.squaredNorm(), (k.c - k.b).squaredNorm()});
  // Collinear to within the rounding of the corners: no surface to sample.
  k.area = (std::isfinite(twice) && twice > 1e-12 * longest) ? 0.5 * twice : 0.0;
  return k;
}

/// Each triangle's area (0: degenerate), the total, the count of degenerate ones and
/// the largest side of the box around the rest.
struct Areas {
  std::vector<double> of;
  double total{0.0};
  std::size_t degenerate{0};
  double extent_m{0.0};
};

Areas measureAreas(const TriangleMesh& mesh, const std::string& path) {
  if (mesh.triangles.empty()) throwNoFaces(path);
  Areas a;
  a.of.resize(mesh.triangles.size());
  Vec3 lo = Vec3::Constant(kInf), hi = -lo;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Corners k = corners(mesh, i, path);
    a.of[i] = k.area;
    if (k.area == 0.0) {
      ++a.degenerate;
      continue;
    }
    a.total += k.area;
    for (const Vec3* p : {&k.a, &k.b, &k.c}) {
      lo = lo.cwiseMin(*p);
      hi = hi.cwiseMax(*p);
    }
  }
  if (a.degenerate == mesh.triangles.size() || !(a.total > 0.0) || !std::isfinite(a.total))
    throw InputError(path + ": every one of the mesh's " + std::to_string(mesh.triangles.size()) +
                     " triangles is degenerate (no area); nothing to sample");
  a.extent_m = (hi - lo).maxCoeff();
  return a;
}

/// The spacing to sample at [m]; throws when it is not usable or gives too many points.
double spacingOf(const Areas& a, const MeshSampleOptions& options, const std::string& path) {
  const double s =
      options.spacing_m == 0.0 ? autoMeshSpacing(a.total, a.extent_m) : options.spacing_m;
  if (!(std::isfinite(s) && s > 0.0))
    throw InputError(path + ": mesh spacing must be > 0 and finite, got " + formatNumber(s));
  const double expected = a.total / (s * s);
  if (expected > static_cast<double>(options.max_points)) {
    const double fits = std::sqrt(a.total / static_cast<double>(options.max_points));
    throw InputError(path + ": sampling " + formatNumber(a.total, 4) + " m2 of mesh every " +
                     formatNumber(s, 4) + " m needs " + formatNumber(expected, 3) +
                     " points, more than " + std::to_string(options.max_points) +
                     " (about 0.5 kB each through the pipeline); set input.mesh_spacing_m >= " +
                     formatNumber(fits, 3));
  }
  return s;
}

/// Points `k` gets: `count` of them, R2 from a seeded offset, folded onto the triangle.
void sampleTriangle(const Corners& k, std::uint64_t count, std::uint64_t seed, std::size_t i,
                    PointList& out) {
  const Vec3 ab = k.b - k.a, ac = k.c - k.a;
  const double o1 = uniform01(seed, i, 1), o2 = uniform01(seed, i, 2);
  for (std::uint64_t j = 0; j < count; ++j) {
    const double step = static_cast<double>(j) + 0.5;
    double r1 = o1 + step * kR2Step1, r2 = o2 + step * kR2Step2;
    r1 -= std::floor(r1);
    r2 -= std::floor(r2);
    if (r1 + r2 > 1.0) {
      r1 = 1.0 - r1;
      r2 = 1.0 - r2;
    }
    out.push_back(k.a + r1 * ab + r2 * ac);
  }
}

}  // namespace

void throwNoFaces(const std::string& path) {
  throw InputError(path +
                   ": the mesh has no triangle faces; give a mesh with faces (or its "
                   "vertices as a cloud: .ply without faces, .pcd, .xyz)");
}

double autoMeshSpacing(double area_m2, double extent_m) {
  return std::max(std::sqrt(area_m2 / kAutoMeshPoints),
                  std::min(kAutoMeshSpacingM, extent_m / 200.0));
}

PointList sampleMesh(const TriangleMesh& mesh, const MeshSampleOptions& options,
                     const std::string& path, MeshReadInfo* info) {
  const Areas a = measureAreas(mesh, path);
  const double s = spacingOf(a, options, path);
  // The counts: area / s² and a seeded fraction per triangle, so the mean density is 1 / s².
  std::vector<std::uint64_t> counts(a.of.size(), 0);
  std::uint64_t n = 0;
  const double per_m2 = 1.0 / (s * s);
  for (std::size_t i = 0; i < a.of.size(); ++i) {
    if (a.of[i] == 0.0) continue;
    counts[i] =
        static_cast<std::uint64_t>(std::floor(a.of[i] * per_m2 + uniform01(options.seed, i, 0)));
    n += counts[i];
  }
  if (n == 0)
    throw InputError(path + ": sampling " + formatNumber(a.total, 4) + " m2 of mesh every " +
                     formatNumber(s, 4) + " m gives no point; set a smaller input.mesh_spacing_m");
  PointList points;
  points.reserve(n);
  for (std::size_t i = 0; i < a.of.size(); ++i) {
    if (counts[i] > 0) sampleTriangle(corners(mesh, i, path), counts[i], options.seed, i, points);
  }
  if (info != nullptr) {
    info->triangles = mesh.triangles.size();
    info->degenerate = a.degenerate;
    info->area_m2 = a.total;
    info->spacing_m = s;
    info->spacing_source = options.spacing_m == 0.0 ? "auto" : "config";
    info->seed = options.seed;
  }
  return points;
}

}  // namespace uavip::io

namespace uavip::io {

TriangleMesh surfaceTriangles(const TriangleMesh& mesh, const std::string& path) {
  TriangleMesh out;
  constexpr auto kUnused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> renumber(mesh.vertices.size(), kUnused);
  out.triangles.reserve(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (corners(mesh, i, path).area == 0.0) continue;
    std::array<std::uint32_t, 3> t{};
    for (int k = 0; k < 3; ++k) {
      std::uint32_t& v = renumber[mesh.triangles[i][static_cast<std::size_t>(k)]];
      if (v == kUnused) {
        v = static_cast<std::uint32_t>(out.vertices.size());
        out.vertices.push_back(mesh.vertices[mesh.triangles[i][static_cast<std::size_t>(k)]]);
      }
      t[static_cast<std::size_t>(k)] = v;
    }
    out.triangles.push_back(t);
  }
  return out;
}

void writeMeshStlFile(const std::string& file, const TriangleMesh& mesh, const std::string& path) {
  std::ofstream out(file, std::ios::binary);
  // Not "solid…": a binary STL whose header starts so is taken for ASCII by readers.
  std::string header = "uavip: a mesh input's triangles, metres, the scene's frame";
  header.resize(80, ' ');
  out.write(header.data(), 80);
  const auto count = static_cast<std::uint32_t>(mesh.triangles.size());
  out.write(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : mesh.triangles) {
    std::array<float, 12> f{};  // normal (left 0: readers recompute it), three corners
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t a = 0; a < 3; ++a)
        f[3 + 3 * k + a] = static_cast<float>(mesh.vertices[t[k]][static_cast<Eigen::Index>(a)]);
    out.write(reinterpret_cast<const char*>(f.data()), sizeof(float) * f.size());
    const std::uint16_t attributes = 0;
    out.write(reinterpret_cast<const char*>(&attributes), 2);
  }
  out.flush();
  if (!out)
    throw InputError(path + ": cannot write the STL file (no permission, or the disk is full)");
}

void saveMeshStl(const std::string& path, const TriangleMesh& mesh) {
  replaceFileAtomic(path, [&](const std::string& tmp) { writeMeshStlFile(tmp, mesh, path); });
}

}  // namespace uavip::io
