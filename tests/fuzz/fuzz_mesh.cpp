// libFuzzer target: uavip's own mesh sampling (io/mesh_reader.h, sampleMesh), not
// Assimp's readers. The input is a mesh: byte 0 the vertex count (mod 64), byte 1 the
// spacing (0: automatic, else byte / 64 m), then the vertices as float x y z (so any
// float: NaN, infinities, huge, denormal), then the triangles as byte triples of
// indices (an index may point past the vertices). sampleMesh may refuse the mesh with
// InputError; anything else (a crash, a sanitizer report, another exception) is a
// finding, and so is a point that is not finite or lies outside the box of the
// vertices. scripts/fuzz.sh.

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "uavip/core/error.h"
#include "uavip/io/mesh_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t vertices = data[0] % 64;
  uavip::io::MeshSampleOptions options;
  options.spacing_m = data[1] / 64.0;
  options.max_points = 200'000;  // the refusal of a large mesh is part of what is fuzzed
  std::size_t at = 2;
  uavip::io::TriangleMesh mesh;
  for (std::size_t v = 0; v < vertices && at + 12 <= size; ++v, at += 12) {
    float f[3];
    std::memcpy(f, data + at, sizeof f);
    mesh.vertices.emplace_back(f[0], f[1], f[2]);
  }
  for (; at + 3 <= size; at += 3) mesh.triangles.push_back({data[at], data[at + 1], data[at + 2]});
  try {
    const uavip::PointList points = uavip::io::sampleMesh(mesh, options, "fuzz");
    uavip::Vec3 lo = uavip::Vec3::Constant(1e308), hi = -lo;
    for (const auto& v : mesh.vertices) {
      if (!v.allFinite()) continue;
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    const double slack = 1e-9 * (1.0 + (hi - lo).norm());
    for (const auto& p : points) {
      if (!p.allFinite()) __builtin_trap();
      if ((p.array() < lo.array() - slack).any() || (p.array() > hi.array() + slack).any())
        __builtin_trap();
    }
  } catch (const uavip::InputError&) {
  }
  return 0;
}
