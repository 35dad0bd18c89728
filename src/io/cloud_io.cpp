// Clouds by extension: the reader of each format (cloud_formats.h), input.scale,
// the recentring of a far cloud, and the streamed reading of `uavip tile`.

#include "uavip/io/cloud_io.h"

#include <pcl/console/print.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "cloud_formats.h"
#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/las_reader.h"
#include "uavip/io/mesh_reader.h"

namespace uavip::io {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

namespace {

/// Reads a PCD (uavip's own reader, pcd_reader.cpp) or PLY (PCL's reader after the
/// header checks, ply_reader.cpp) file into a PCLPointCloud2.
pcl::PCLPointCloud2 readBlob(const std::string& path, const std::string& ext) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read (permission?)");
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path + ": cannot read its size (" + ec.message() + ")");
  if (ext == ".pcd") return readPcd(path, in, size);
  return readPly(path, in, size);
}

/// A mesh's surface sampled into points, input.scale applied (io/mesh_reader.h); the
/// read line and the mesh record go to `info`.
PointList readMeshPoints(const std::string& path, const CloudReadOptions& options,
                         CloudReadInfo* info) {
  MeshReadInfo mesh;
  MeshSampleOptions sample;
  sample.spacing_m = options.mesh_spacing_m;
  const TriangleMesh triangles = readMesh(path, options.scale, &mesh);
  PointList points = sampleMesh(triangles, sample, path, &mesh);
  if (info != nullptr) {
    info->triangles = std::make_shared<const TriangleMesh>(surfaceTriangles(triangles, path));
    // The key as the config writes it ("input." + the table's row).
    const std::string key =
        "input." + CloudReadOptions::table().find(options, &options.mesh_spacing_m)->key;
    std::ostringstream os;
    os << path << ": mesh (" << mesh.format << "), " << mesh.triangles << " triangles";
    if (mesh.degenerate > 0) os << " (" << mesh.degenerate << " without area, skipped)";
    os << ", " << formatNumber(mesh.area_m2, 4) << " m2, sampled every "
       << formatNumber(mesh.spacing_m, 3) << " m ("
       << (mesh.spacing_source == "auto" ? "auto; set " + key + " to change" : key)
       << "): " << points.size() << " points; " << mesh.axes;
    if (options.scale != 1.0)
      os << "; coordinates scaled by input.scale " << formatNumber(options.scale);
    info->note = os.str();
    info->mesh = mesh;
  }
  return points;
}

/// A mesh's triangles moved into the frame of its points (by `shift`, the recentring)
/// and rounded to float, as the copy beside scene.json holds them; nothing for a cloud.
void placeMeshTriangles(CloudReadInfo& info, const Vec3& shift) {
  if (!info.triangles) return;
  auto placed = std::make_shared<TriangleMesh>(*info.triangles);
  for (Vec3& v : placed->vertices) v = (v - shift).cast<float>().cast<double>();
  info.triangles = std::move(placed);
}

/// What loadCloud and streamCloud say of an extension no reader knows.
[[noreturn]] void unknownExtension(const std::string& path, const std::string& ext) {
  throw InputError(path + ": unknown cloud extension '" + ext +
                   "' (clouds: .pcd, .ply, .xyz, .txt, .csv, .las; meshes: .stl, .obj, .ply with "
                   "faces, .gltf, .glb, .dae, .fbx, .3ds, .off)");
}

}  // namespace

void CloudReadOptions::validate(const std::string& where) const { table().check(*this, where); }

const params::Table<CloudReadOptions>& CloudReadOptions::table() {
  static const params::Table<CloudReadOptions> t = [] {
    using O = CloudReadOptions;
    params::Table<O> p;
    p.add("drop_classes", &O::drop_classes,
          "LAS only: ASPRS classes whose points are dropped ([] keeps every point)")
        .count(0, 256)
        .within(0, 255)
        .integral();
    p.add("scale", &O::scale,
          "× every coordinate to give metres: 0.001 for millimetres, 0.3048 for international "
          "feet")
        .positive();
    p.add("mesh_spacing_m", &O::mesh_spacing_m,
          "meshes: distance between the points sampled on the triangles (0: chosen from the "
          "mesh's area and size)")
        .unitIs("m")
        .atLeast(0);
    return p;
  }();
  return t;
}

PointList loadCloud(const std::string& path, const CloudReadOptions& options, CloudReadInfo* info) {
  options.validate();
  const std::string ext = lowerExtension(path);
  requireRegularFile(path);
  PointList points;
  Vec3 origin = Vec3::Zero();  // already subtracted from points (LAS)
  bool scaled = false;         // input.scale already applied (a mesh, sampled in metres)
  if (ext == ".las" || ext == ".laz") {
    LasOptions las_options;
    las_options.drop_classes = options.drop_classes;
    LasCloud las = readLas(path, las_options);
    if (info != nullptr) {
      std::ostringstream os;
      os << path << ": LAS " << las.version_major << "." << las.version_minor << " point format "
         << las.point_format << ", " << las.points_in_file << " points";
      if (!options.drop_classes.empty()) {
        os << " (" << las.dropped << " dropped: input.drop_classes";
        for (const int c : options.drop_classes) os << " " << c;
        os << (options.drop_classes == std::vector<int>{7, 18} ? ", the classes LAS flags as noise"
                                                               : "")
           << ")";
      }
      os << "; unit " << las.unit_name << " (" << las.unit_source << ")";
      if (las.unit_to_m != 1.0 || las.z_unit_to_m != 1.0) os << " converted to metres";
      os << "; recentred by (" << formatNumber(las.origin_m.x(), 12) << ", "
         << formatNumber(las.origin_m.y(), 12) << ", " << formatNumber(las.origin_m.z(), 12)
         << ") m";  // every metre of a UTM northing
      if (!las.crs.empty()) os << "; CRS from " << las.crs_source;
      info->note = os.str();
      info->origin_m = las.origin_m;
      info->crs = las.crs;
      info->crs_source = las.crs_source;
    }
    origin = las.origin_m;
    points = std::move(las.points);
    if (points.empty())
      throw InputError(path + ": no point is left after drop_classes; drop fewer classes");
  } else if (ext == ".xyz" || ext == ".txt" || ext == ".csv") {
    points = loadXyz(path);
  } else if (isMeshFile(path)) {
    points = readMeshPoints(path, options, info);
    scaled = true;
  } else if (ext == ".pcd" || ext == ".ply") {
    points = fromBlob(readBlob(path, ext), path);
  } else {
    unknownExtension(path, ext);
  }
  if (points.empty()) throw InputError(path + ": the cloud has no points");
  if (options.scale != 1.0 && !scaled) {
    for (auto& p : points) p *= options.scale;
    origin *= options.scale;
    if (info != nullptr) {
      info->note += std::string(info->note.empty() ? "" : "; ") +
                    "coordinates scaled by input.scale " + formatNumber(options.scale) +
                    " to metres";
      info->origin_m = origin;
    }
  }
  Vec3 lo = points.front(), hi = points.front();
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  requirePhysicalExtent(path, points, lo, hi, origin);
  // A cloud far from the origin (UTM, a national grid): recentred while still in double.
  if (farFromOrigin(lo, hi)) {
    const Vec3 shift = recentringOrigin(lo, hi);
    for (Vec3& p : points) p -= shift;
    origin += shift;
    if (info != nullptr) {
      info->origin_m = origin;
      info->note += std::string(info->note.empty() ? path + ": " : "; ") +
                    "far from the origin, recentred by (" + formatNumber(shift.x(), 12) + ", " +
                    formatNumber(shift.y(), 12) + ", " + formatNumber(shift.z(), 12) +
                    ") m (scene.json source_offset_m adds it back)";
    }
  }
  if (info != nullptr) placeMeshTriangles(*info, origin);  // a mesh's origin: the recentring
  return points;
}

namespace {

/// An ascii or binary PCD file, or an ascii or binary_little_endian PLY one (of
/// points), streamed to `sink`; false for the others (read whole).
bool streamBlobChunks(const std::string& path, const std::string& ext, std::size_t chunk_points,
                      const std::function<void(const PointList&)>& sink) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read (permission?)");
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path + ": cannot read its size (" + ec.message() + ")");
  if (ext == ".pcd") return streamPcd(path, in, size, chunk_points, sink);
  return streamPly(path, in, size, chunk_points, sink);
}

/// One pass over the cloud in the frame loadCloud gives before its own recentring
/// (a LAS file recentred by its header, then input.scale), in chunks to `sink`.
/// Returns the LAS header information for LAS files (nullopt otherwise).
/// `on_las_header`, if set, sees a LAS file's header (its origin_m) before the first chunk.
std::optional<LasCloud> readChunks(const std::string& path, const CloudReadOptions& options,
                                   std::size_t chunk_points, const CloudChunkSink& sink,
                                   const std::function<void(const LasCloud&)>& on_las_header = {}) {
  const std::string ext = lowerExtension(path);
  PointList chunk;
  chunk.reserve(chunk_points);
  double scale = options.scale;  // 1 for a mesh: sampled in metres
  const auto flush = [&] {
    if (chunk.empty()) return;
    if (scale != 1.0)
      for (Vec3& p : chunk) p *= scale;
    sink(chunk);
    chunk.clear();
  };
  const auto add = [&](const Vec3& p) {
    chunk.push_back(p);
    if (chunk.size() >= chunk_points) flush();
  };
  std::optional<LasCloud> las;
  if (ext == ".las" || ext == ".laz") {
    LasOptions las_options;
    las_options.drop_classes = options.drop_classes;
    las = streamLas(
        path, las_options,
        [&](const PointList& points, const std::vector<std::uint8_t>&) {
          for (const Vec3& p : points) add(p);
        },
        on_las_header);
  } else if (ext == ".xyz" || ext == ".txt" || ext == ".csv") {
    std::ifstream in(path);
    if (!in) throw InputError(path + ": cannot open the file, check its permissions");
    parseXyz(in, path, add);
  } else if (isMeshFile(path)) {
    // A mesh is sampled whole, then handed on in chunks.
    scale = 1.0;
    for (const Vec3& p : readMeshPoints(path, options, nullptr)) add(p);
  } else if ((ext == ".pcd" || ext == ".ply") &&
             streamBlobChunks(path, ext, chunk_points, [&](const PointList& points) {
               for (const Vec3& p : points) add(p);
             })) {
    // ascii and binary PCD, ascii and binary_little_endian PLY: streamed
  } else if (ext == ".pcd" || ext == ".ply") {
    // binary_compressed PCD (one LZF block) and the other PLY files are read whole
    // (PCL's blob), then handed on in chunks.
    for (const Vec3& p : fromBlob(readBlob(path, ext), path)) add(p);
  } else {
    unknownExtension(path, ext);
  }
  flush();
  return las;
}

}  // namespace

bool streamsInBoundedMemory(const std::string& path) {
  const std::string ext = lowerExtension(path);
  if (ext == ".pcd" || (ext == ".ply" && !isMeshFile(path))) {  // the header alone is read
    std::ifstream in(path, std::ios::binary);
    std::error_code ec;
    const std::uint64_t size = std::filesystem::file_size(path, ec);
    try {
      return in && !ec && (ext == ".pcd" ? pcdStreams(path, in, size) : plyStreams(path, in, size));
    } catch (const InputError&) {
      return false;
    }
  }
  return ext == ".las" || ext == ".xyz" || ext == ".txt" || ext == ".csv";
}

namespace {

/// The bounds of the points seen, in the frame readChunks hands them (before the
/// recentring), each point checked against kMaxCoordinateM.
struct BoundsCheck {
  const std::string& path;
  Vec3 lo{Vec3::Constant(std::numeric_limits<double>::infinity())}, hi{-lo};
  std::uint64_t points{0};
  void add(const PointList& chunk) {
    for (const Vec3& p : chunk) {
      if (p.cwiseAbs().maxCoeff() > kMaxCoordinateM)
        throw InputError(path + ": point " + formatRawPoint(p) + " lies beyond " +
                         formatNumber(kMaxCoordinateM / 1e3) +
                         " km of the origin; remove it or fix input.scale");
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    points += chunk.size();
  }
  /// The stream's info (loadCloud's frame) once every point is seen: refuses an empty
  /// or too wide cloud; `shift` gets the recentring beyond a LAS file's own.
  CloudStreamInfo finish(const CloudReadOptions& options, const std::optional<LasCloud>& las,
                         Vec3& shift) const {
    if (points == 0)
      throw InputError(path + (las ? ": no point is left after drop_classes; drop fewer classes"
                                   : ": the cloud has no points"));
    if ((hi - lo).maxCoeff() > kMaxCloudExtentM)
      throw InputError(path + ": the cloud spans " + formatNumber((hi - lo).maxCoeff() / 1e3, 4) +
                       " km, wider than " + formatNumber(kMaxCloudExtentM / 1e3) +
                       " km: it is not in metres (set input.scale) or holds a stray point");
    CloudStreamInfo info;
    info.points = points;
    Vec3 origin = las ? Vec3(las->origin_m * options.scale) : Vec3::Zero();
    shift = farFromOrigin(lo, hi) ? recentringOrigin(lo, hi) : Vec3::Zero();
    origin += shift;
    info.read.origin_m = origin;
    info.min = lo - shift;
    info.max = hi - shift;
    if (las) {
      info.crs_unit = las->unit_name + " (" + las->unit_source + ")";
      info.read.crs = las->crs;
      info.read.crs_source = las->crs_source;
      info.read.note = path + ": LAS " + std::to_string(las->version_major) + "." +
                       std::to_string(las->version_minor) + ", " +
                       std::to_string(las->points_in_file) + " points, " +
                       std::to_string(las->dropped) + " dropped by input.drop_classes";
    }
    return info;
  }
};

/// `points` less `shift` to `sink` (as they are when `shift` is zero).
void handShifted(const PointList& points, const Vec3& shift, const CloudChunkSink& sink) {
  if (shift == Vec3::Zero()) {
    sink(points);
    return;
  }
  PointList shifted = points;
  for (Vec3& p : shifted) p -= shift;
  sink(shifted);
}

}  // namespace

CloudStreamInfo streamCloud(const std::string& path, const CloudReadOptions& options,
                            std::size_t chunk_points, const CloudChunkSink& sink,
                            const std::function<void(const CloudStreamInfo&)>& on_bounds) {
  options.validate();
  requireRegularFile(path);
  if (chunk_points == 0) throw InputError("streamCloud: chunk_points must be > 0");
  // Pass 1: count and bounds, so that the frame is loadCloud's before any point is handed on.
  BoundsCheck bounds{path};
  const std::optional<LasCloud> las =
      readChunks(path, options, chunk_points, [&](const PointList& points) { bounds.add(points); });
  Vec3 shift = Vec3::Zero();
  CloudStreamInfo info = bounds.finish(options, las, shift);
  if (on_bounds) on_bounds(info);
  // Pass 2: the points in that frame.
  readChunks(path, options, chunk_points,
             [&](const PointList& points) { handShifted(points, shift, sink); });
  return info;
}

CloudStreamInfo streamCloudInFrame(const std::string& path, const CloudReadOptions& options,
                                   const Vec3& origin_m, std::size_t chunk_points,
                                   const CloudChunkSink& sink) {
  options.validate();
  requireRegularFile(path);
  if (chunk_points == 0) throw InputError("streamCloudInFrame: chunk_points must be > 0");
  BoundsCheck bounds{path};
  Vec3 shift = origin_m;  // less a LAS file's own recentring, known from its header
  const std::optional<LasCloud> las = readChunks(
      path, options, chunk_points,
      [&](const PointList& points) {
        bounds.add(points);
        handShifted(points, shift, sink);
      },
      [&](const LasCloud& header) { shift = origin_m - header.origin_m * options.scale; });
  Vec3 unused = Vec3::Zero();
  return bounds.finish(options, las, unused);
}

PointColours loadCloudColours(const std::string& path) {
  const std::string ext = lowerExtension(path);
  if ((ext != ".pcd" && ext != ".ply") || isMeshFile(path)) return {};
  return coloursFromBlob(readBlob(path, ext));
}

void setPclConsole(bool verbose) {
  pcl::console::setVerbosityLevel(verbose ? pcl::console::L_WARN : pcl::console::L_ALWAYS);
}

}  // namespace uavip::io
