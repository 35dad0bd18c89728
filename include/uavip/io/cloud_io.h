#pragma once
/// \file
/// Point cloud files: PCD and PLY (PCL readers/writers) and XYZ text
/// ("x y z" per line, extra columns ignored, '#' comments); triangle meshes are read
/// as the points sampled on their surface (io/mesh_reader.h).

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "uavip/core/params.h"
#include "uavip/core/types.h"
#include "uavip/io/mesh_reader.h"

namespace uavip::io {

/// How a cloud file is read (YAML section `input:`).
struct CloudReadOptions {
  /// LAS only: ASPRS classes whose points are dropped. Default: the ones the file
  /// itself flags as noise, 7 (low point) and 18 (high noise), said on the read line;
  /// `[]` keeps every point, `[3, 4, 5, 7, 18]` drops vegetation too. Nothing else
  /// removes a measured point from safety (preprocess/safety_cloud.h).
  std::vector<int> drop_classes{7, 18};
  /// Every coordinate is multiplied by this to give metres, after a LAS file's own
  /// unit conversion: 0.001 for a cloud in millimetres, 0.01 in centimetres, 0.3048
  /// in international feet. 1 = the file is in metres (or a LAS file says its unit).
  double scale{1.0};
  /// Meshes only: the sampling spacing [m], one point per spacing² of surface on
  /// average; 0 = chosen from the mesh's area and size (io::autoMeshSpacing).
  double mesh_spacing_m{0.0};
  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "input") const;
  /// The keys of `input:` this struct holds (core/params.h).
  static const params::Table<CloudReadOptions>& table();
};

/// What reading did besides returning points (for the printout and scene.json).
struct CloudReadInfo {
  std::string note;  ///< one line, e.g. the unit conversion of a LAS file; empty if none
  /// The cloud's CRS as PROJ reads it (a LAS file's WKT or EPSG code; detect --crs);
  /// empty when nothing states one.
  std::string crs;
  std::string crs_source;  ///< where crs came from ("LAS WKT record 2112", "detect --crs")
  /// What heights are measured from: "egm96", "egm2008", "ellipsoid", or empty (unknown).
  std::string crs_vertical;
  Vec3 origin_m{
      Vec3::Zero()};  ///< subtracted from the file's coordinates (after unit conversion) [m]
  MeshReadInfo mesh;  ///< the mesh read and how it was sampled; mesh.present false for a cloud
  /// A mesh's triangles with area (io::surfaceTriangles) in the frame of the points
  /// loadCloud returns (recentred with them), vertices rounded to float; null for a cloud.
  std::shared_ptr<const TriangleMesh> triangles;
};

/// A cloud whose bounding box reaches farther than this from the file's origin, on
/// any axis, is recentred by every reader (LAS always recentres x and y) [m]. A float
/// keeps 1 mm at 10 km, and OctoMap's keys reach ±6.5 km at 0.2 m voxels.
constexpr double kRecentreBeyondM = 1.0e4;

/// A cloud wider than this on any axis is refused (exit 2) [m]: no structure a UAV
/// inspects is 100 km across; such a cloud holds a stray point (e.g. 1e308) or is in
/// the wrong unit.
constexpr double kMaxCloudExtentM = 1.0e5;

/// A coordinate beyond this is refused (exit 2) [m]: 100,000 km, more than twice the
/// earth's circumference, so no CRS on earth gives it (a lone point at 1e308 would
/// otherwise be "recentred").
constexpr double kMaxCoordinateM = 1.0e8;

/// The origin a reader subtracts from a cloud whose bounding box (file coordinates,
/// metres) is [lo, hi]: x and y the box's centre rounded to whole metres; z 0 (the
/// elevations are kept) unless the z range lies beyond kRecentreBeyondM, then its
/// rounded centre too. The one rule of the LAS, PCD, PLY and text readers.
Vec3 recentringOrigin(const Vec3& lo, const Vec3& hi);

/// True when the box [lo, hi] reaches beyond kRecentreBeyondM of the origin on any axis:
/// the PCD, PLY and text readers recentre such a cloud (recentringOrigin).
bool farFromOrigin(const Vec3& lo, const Vec3& hi);

/// Reads a cloud by extension (.pcd, .ply, .las; .xyz, .txt and .csv: x y z first on
/// each line, separated by spaces, tabs or commas, one optional header line of
/// names such as "x,y,z" or "//X Y Z Intensity"; .laz is refused with the command
/// that decompresses it), then applies options.scale. A mesh (io::isMeshFile: .stl,
/// .obj, .gltf, .glb, .ply with faces, …) is read by Assimp, scaled and sampled at
/// options.mesh_spacing_m (io::sampleMesh; info->mesh records how). Every coordinate is read as a
/// double; a cloud far from the origin (farFromOrigin; a LAS file always) is recentred
/// by recentringOrigin before anything becomes float, said in info->note, and
/// info->origin_m holds the offset (scene.json's source_offset_m). Throws InputError
/// naming the file for a missing or unreadable file, an unknown extension, an empty
/// cloud, a non-finite point (with its index or line), a coordinate beyond
/// kMaxCoordinateM (naming the point), or a cloud wider than
/// kMaxCloudExtentM (naming the point farthest from the cloud's median when at most
/// 1 % of the points lie far from it, else pointing at input.scale).
PointList loadCloud(const std::string& path, const CloudReadOptions& options = {},
                    CloudReadInfo* info = nullptr);

/// What colour a cloud file gives its points (for a preview of photos, uavip photos).
struct PointColours {
  std::vector<std::array<std::uint8_t, 3>> rgb;  ///< one per point; empty: the file has none
  std::string source;  ///< the field(s) read: "rgb", "red,green,blue", "intensity", ...
};

/// The colour of every point loadCloud returns for `path`, in the same order: a PCD or
/// PLY file's packed rgb/rgba or its red, green, blue fields (16-bit ones scaled), else
/// its intensity as grey (stretched between its 1st and 99th percentiles). Empty when
/// the file has none, or is not PCD/PLY (LAS, text and meshes are not read for colour).
/// Throws InputError like loadCloud for an unreadable file.
PointColours loadCloudColours(const std::string& path);

/// Receives one chunk of points [m] of a streamed cloud.
using CloudChunkSink = std::function<void(const PointList& points)>;

/// What streamCloud read.
struct CloudStreamInfo {
  std::uint64_t points{0};  ///< points handed on (after drop_classes)
  Vec3 min{Vec3::Zero()};   ///< bounding box of the handed-on points [m]
  Vec3 max{Vec3::Zero()};   ///< [m]
  CloudReadInfo read;       ///< origin_m: as loadCloud's; note: a LAS file's summary; its CRS
  std::string crs_unit;     ///< a LAS file's unit and where it came from; else empty
};

/// True when streamCloud reads `path` in bounded memory (LAS, x y z text, ascii and
/// binary PCD, ascii and binary_little_endian PLY of points whose vertex element comes
/// first with scalar properties only); binary_compressed PCD (one LZF block), other
/// PLY files and meshes are read whole and then handed on in chunks.
bool streamsInBoundedMemory(const std::string& path);

/// The points loadCloud would return, in the same frame (same origin_m, same
/// doubles), handed to `sink` in file order in chunks of at most `chunk_points`,
/// without holding the cloud (see streamsInBoundedMemory): one pass for the count and
/// bounds, one for the points; `on_bounds`, if set, sees the count, bounds and origin
/// between them. Throws InputError naming the file like loadCloud (an empty cloud, a
/// non-finite point, a coordinate beyond kMaxCoordinateM, a cloud wider than
/// kMaxCloudExtentM).
CloudStreamInfo streamCloud(const std::string& path, const CloudReadOptions& options,
                            std::size_t chunk_points, const CloudChunkSink& sink,
                            const std::function<void(const CloudStreamInfo&)>& on_bounds = {});

/// streamCloud in one pass when the frame is known (e.g. a tiling manifest's
/// source_offset_m): the points loadCloud would return had it subtracted `origin_m`,
/// handed to `sink` as they are read. The returned info (origin_m, bounds, count) is
/// streamCloud's, found on the way: the caller compares info.read.origin_m with
/// `origin_m` (they differ only for a file changed since the frame was found). The
/// same errors as streamCloud, raised once every point is read.
CloudStreamInfo streamCloudInFrame(const std::string& path, const CloudReadOptions& options,
                                   const Vec3& origin_m, std::size_t chunk_points,
                                   const CloudChunkSink& sink);

/// PCL prints warnings and errors of its own on stderr (e.g. a RANSAC model with too
/// few inliers, which uavip handles): they are silenced unless `verbose`, so that an
/// error is one uavip line.
void setPclConsole(bool verbose);

/// Writes a binary PCD atomically (temporary file + rename). Throws InputError naming
/// `path` on I/O failure.
void saveCloudPcd(const std::string& path, const PointList& cloud);

/// Writes a binary PCD to `file` as it is (a staged temporary, io/atomic_file.h);
/// messages name `path`, the file the user will see.
void writeCloudPcdFile(const std::string& file, const PointList& cloud, const std::string& path);

}  // namespace uavip::io
