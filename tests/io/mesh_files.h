#pragma once
// Mesh files written by the tests themselves (STL ascii and binary, OBJ, PLY, glTF
// with an embedded buffer), and the exact point-triangle distance they check against.

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "uavip/core/types.h"

namespace uavip::mesh_test {

/// A triangle soup [m].
using Triangles = std::vector<std::array<Vec3, 3>>;

/// The 12 triangles of the box [lo, hi], outward.
inline Triangles boxTriangles(const Vec3& lo, const Vec3& hi) {
  const auto c = [&](int i) {
    return Vec3(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  };
  // Each face as a quad a b c d, counter-clockwise seen from outside.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  Triangles t;
  for (const auto& q : quads) {
    t.push_back({c(q[0]), c(q[1]), c(q[2])});
    t.push_back({c(q[0]), c(q[2]), c(q[3])});
  }
  return t;
}

/// The rectangle corner + s u + t v cut into n x n cells of two triangles each.
inline Triangles gridTriangles(const Vec3& corner, const Vec3& u, const Vec3& v, int n) {
  Triangles t;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const Vec3 a = corner + (u * i + v * j) / n, b = corner + (u * (i + 1) + v * j) / n;
      const Vec3 c = corner + (u * (i + 1) + v * (j + 1)) / n,
                 d = corner + (u * i + v * (j + 1)) / n;
      t.push_back({a, b, c});
      t.push_back({a, c, d});
    }
  }
  return t;
}

inline void writeStlAscii(const std::string& path, const Triangles& tris) {
  std::ofstream out(path);
  out.precision(17);
  out << "solid test\n";
  for (const auto& t : tris) {
    out << " facet normal 0 0 0\n  outer loop\n";
    for (const Vec3& p : t) out << "   vertex " << p.x() << " " << p.y() << " " << p.z() << "\n";
    out << "  endloop\n endfacet\n";
  }
  out << "endsolid test\n";
}

inline void writeStlBinary(const std::string& path, const Triangles& tris) {
  std::ofstream out(path, std::ios::binary);
  const std::string header(80, ' ');
  out.write(header.data(), 80);
  const auto count = static_cast<std::uint32_t>(tris.size());
  out.write(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : tris) {
    float f[12] = {0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) f[3 + 3 * k + a] = static_cast<float>(t[k][a]);
    out.write(reinterpret_cast<const char*>(f), sizeof f);
    const std::uint16_t attributes = 0;
    out.write(reinterpret_cast<const char*>(&attributes), 2);
  }
}

inline void writeObj(const std::string& path, const Triangles& tris) {
  std::ofstream out(path);
  out.precision(17);
  for (const auto& t : tris)
    for (const Vec3& p : t) out << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
  for (std::size_t i = 0; i < tris.size(); ++i)
    out << "f " << 3 * i + 1 << " " << 3 * i + 2 << " " << 3 * i + 3 << "\n";
}

/// An ascii PLY with the triangles as faces (faces false: the vertices only).
inline void writePly(const std::string& path, const Triangles& tris, bool faces) {
  std::ofstream out(path);
  out.precision(17);
  out << "ply\nformat ascii 1.0\nelement vertex " << 3 * tris.size()
      << "\nproperty double x\nproperty double y\nproperty double z\n";
  if (faces) out << "element face " << tris.size() << "\nproperty list uchar int vertex_indices\n";
  out << "end_header\n";
  for (const auto& t : tris)
    for (const Vec3& p : t) out << p.x() << " " << p.y() << " " << p.z() << "\n";
  if (faces)
    for (std::size_t i = 0; i < tris.size(); ++i)
      out << "3 " << 3 * i << " " << 3 * i + 1 << " " << 3 * i + 2 << "\n";
}

inline std::string base64(const std::string& bytes) {
  static const char* const k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t v = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<std::uint8_t>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<std::uint8_t>(bytes[i + 2]);
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? k[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? k[v & 63] : '=';
  }
  return out;
}

/// A glTF 2.0 file of the triangles (as given: y up is the file's convention), its
/// float positions in one buffer embedded as a base64 data URI, the mesh's node moved
/// by `translation` (in the file's frame).
inline void writeGltf(const std::string& path, const Triangles& tris,
                      const Vec3& translation = Vec3::Zero()) {
  std::string bin;
  Vec3 lo = tris[0][0], hi = lo;
  for (const auto& t : tris) {
    for (const Vec3& p : t) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      for (int a = 0; a < 3; ++a) {
        const float f = static_cast<float>(p[a]);
        char b[4];
        std::memcpy(b, &f, 4);
        bin.append(b, 4);
      }
    }
  }
  std::ofstream out(path);
  out.precision(9);
  out << "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0]}],"
      << " \"nodes\": [{\"mesh\": 0, \"translation\": [" << translation.x() << ", "
      << translation.y() << ", " << translation.z() << "]}],"
      << " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"mode\": 4}]}],"
      << " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": "
      << 3 * tris.size() << ", \"type\": \"VEC3\", \"min\": [" << lo.x() << ", " << lo.y() << ", "
      << lo.z() << "], \"max\": [" << hi.x() << ", " << hi.y() << ", " << hi.z() << "]}],"
      << " \"bufferViews\": [{\"buffer\": 0, \"byteLength\": " << bin.size() << "}],"
      << " \"buffers\": [{\"byteLength\": " << bin.size()
      << ", \"uri\": \"data:application/octet-stream;base64," << base64(bin) << "\"}]}\n";
}

/// Exact distance from p to the triangle (a, b, c) (Ericson, Real-Time Collision
/// Detection, 5.1.5: the closest point by Voronoi regions).
inline double pointTriangleDistance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return (p - a).norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double denom = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

/// Distance from p to the nearest triangle of `tris` (brute force).
inline double distanceToMesh(const Vec3& p, const Triangles& tris) {
  double best = 1e300;
  for (const auto& t : tris) best = std::min(best, pointTriangleDistance(p, t[0], t[1], t[2]));
  return best;
}

/// Distance from segment [a, b] to the triangle t, by golden-section search on
/// pointTriangleDistance along the segment (convex along it: t is convex).
inline double segmentTriangleDistance(const Vec3& a, const Vec3& b, const std::array<Vec3, 3>& t) {
  const auto f = [&](double s) { return pointTriangleDistance(a + s * (b - a), t[0], t[1], t[2]); };
  double l = 0.0, r = 1.0;
  constexpr double kGolden = 0.6180339887498949;
  double m1 = r - kGolden * (r - l), m2 = l + kGolden * (r - l);
  double f1 = f(m1), f2 = f(m2);
  for (int i = 0; i < 80; ++i) {
    if (f1 < f2) {
      r = m2;
      m2 = m1;
      f2 = f1;
      m1 = r - kGolden * (r - l);
      f1 = f(m1);
    } else {
      l = m1;
      m1 = m2;
      f1 = f2;
      m2 = l + kGolden * (r - l);
      f2 = f(m2);
    }
  }
  return std::min({f(0.0), f(1.0), f1, f2});
}

/// Distance from the polyline `path` to the nearest triangle of `tris` (brute force
/// over every segment and every triangle).
inline double pathDistanceToMesh(const std::vector<Vec3>& path, const Triangles& tris) {
  double best = 1e300;
  for (std::size_t i = 0; i + 1 < path.size() || (path.size() == 1 && i == 0); ++i) {
    const Vec3& a = path[i];
    const Vec3& b = path.size() == 1 ? a : path[i + 1];
    for (const auto& t : tris) best = std::min(best, segmentTriangleDistance(a, b, t));
  }
  return best;
}

}  // namespace uavip::mesh_test
