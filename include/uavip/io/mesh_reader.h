#pragma once
/// \file
/// Triangle meshes as input (STL, OBJ, PLY with faces, glTF/GLB, COLLADA, FBX, 3DS,
/// OFF and whatever else Assimp reads), turned into a point cloud by sampling the
/// triangles' surface: io::loadCloud reads a mesh through these and the rest of the
/// pipeline sees points as from any cloud.
///
/// Sampling (sampleMesh): triangle i of area a_i gets ⌊a_i / s² + u_i⌋ points, u_i a
/// uniform number in [0, 1) drawn from (seed, i) alone, so the expected density is
/// 1 / s² on every triangle (area-uniform, also over triangles smaller than s²). Inside
/// a triangle the points follow the R2 low-discrepancy sequence (Roberts 2018) from an
/// offset drawn from (seed, i), folded from the unit square onto the triangle
/// (p = A + r1 (B − A) + r2 (C − A), r1 + r2 > 1 reflected): uniform and spread
/// evenly, without clumps. Every point depends only on (seed, i, k): the same mesh
/// gives the same points in the same order, whatever the thread count.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "uavip/core/types.h"

namespace uavip::io {

/// Triangles over shared vertices, in metres once read (readMesh applies input.scale).
using TriangleMesh = uavip::TriangleMesh;

/// What a mesh read recorded (scene.json input_read.mesh; absent for a cloud).
struct MeshReadInfo {
  bool present{false};        ///< true when the input was a mesh
  std::string format;         ///< the file's extension without the dot, e.g. "stl", "glb"
  std::size_t triangles{0};   ///< triangles read (after triangulating polygons)
  std::size_t degenerate{0};  ///< of those, without area (skipped)
  double area_m2{0.0};        ///< total area sampled [m²]
  double spacing_m{0.0};      ///< sampling spacing s: one point per s² on average [m]
  /// Where the spacing came from: "config" (input.mesh_spacing_m) or "auto" (sampleMesh).
  std::string spacing_source;
  std::uint64_t seed{0};  ///< the sampling seed
  double scale{1.0};      ///< input.scale applied to the file's coordinates
  /// How the file's axes were read: "z up as in the file", or "y up turned to z up"
  /// (glTF/GLB by their specification, COLLADA and 3DS as Assimp hands them over).
  std::string axes;
};

/// How a mesh is turned into points.
struct MeshSampleOptions {
  /// Spacing s [m]: one point per s² of surface on average; 0 = automatic
  /// (autoMeshSpacing).
  double spacing_m{0.0};
  std::uint64_t seed{0x6d657368};  ///< the same seed, the same points
  /// A mesh needing more points than this at its spacing is refused (exit 2) before
  /// any is made, naming the spacing that fits: each point costs about 0.5 kB through
  /// the pipeline (kd-trees, safety cloud, grid), so 2e7 points need ~10 GB.
  std::uint64_t max_points{20'000'000};
};

/// Mesh spacing chosen from the mesh's scale [m]: the larger of sqrt(area /
/// kAutoMeshPoints) (so a large mesh gives at most kAutoMeshPoints points) and
/// min(kAutoMeshSpacingM, extent / 200) (a 5 cm lattice like a dense scan, finer for
/// an object under 10 m). `area_m2` the total area, `extent_m` the largest side of
/// the bounding box.
double autoMeshSpacing(double area_m2, double extent_m);
/// Points an automatic spacing gives at most.
constexpr double kAutoMeshPoints = 2.0e6;
/// Automatic spacing on a structure over 10 m [m].
constexpr double kAutoMeshSpacingM = 0.05;

/// The points of `mesh`'s surface (see the file comment), in triangle order. Skips
/// degenerate triangles (no area, or non-finite). Throws InputError naming `path`
/// when a triangle indexes past the vertices, a vertex is not finite, every triangle
/// is degenerate (or there is none), the spacing is not > 0 and finite, or the count
/// exceeds options.max_points. `info` (if given) receives the counts, area and spacing.
PointList sampleMesh(const TriangleMesh& mesh, const MeshSampleOptions& options,
                     const std::string& path, MeshReadInfo* info = nullptr);

/// Assimp reads coordinates in single precision: a mesh whose farthest coordinate is
/// rounded by more than this is refused (exit 2) [m]; about 170 km from its file's origin.
constexpr double kMaxMeshRoundingM = 0.01;

/// True when `path` is read as a mesh: an extension of a mesh format (.stl, .obj,
/// .gltf, .glb, .dae, .fbx, .3ds, .off, or another Assimp reads that is not a cloud
/// format), or a .ply file whose header declares at least one face.
bool isMeshFile(const std::string& path);

/// The triangles of a mesh file read by Assimp (polygons triangulated, node transforms
/// applied, points and lines left out), every coordinate multiplied by `scale`;
/// glTF/GLB (y up by their specification) and COLLADA/3DS (y up once Assimp has read
/// them) turned to z up: (x, y, z) → (x, −z, y). `info` receives format, scale, axes,
/// triangles. Throws InputError naming the file when Assimp cannot read it, it holds
/// no triangle, or its coordinates reach so far that single precision rounds them by
/// more than kMaxMeshRoundingM.
TriangleMesh readMesh(const std::string& path, double scale, MeshReadInfo* info = nullptr);

/// The triangles of `mesh` with area (those sampleMesh samples; a degenerate one has
/// no surface), over the vertices they use, in order. Throws InputError naming `path`
/// like sampleMesh for a bad index or a non-finite vertex.
TriangleMesh surfaceTriangles(const TriangleMesh& mesh, const std::string& path);

/// Writes `mesh` as a binary STL (float coordinates, as they are) atomically: the
/// triangles of a mesh input beside scene.json (io/scene_json.h, kSafetyMeshFile),
/// read back by readMesh(path, 1.0). Throws InputError naming `path` on I/O failure.
void saveMeshStl(const std::string& path, const TriangleMesh& mesh);
/// As saveMeshStl, to `file` as it is (a staged temporary, io/atomic_file.h);
/// messages name `path`.
void writeMeshStlFile(const std::string& file, const TriangleMesh& mesh, const std::string& path);

}  // namespace uavip::io
