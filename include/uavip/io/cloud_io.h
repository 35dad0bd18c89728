#pragma once
/// \file
/// Point cloud files: PCD and PLY (PCL readers/writers) and XYZ text
/// ("x y z" per line, extra columns ignored, '#' comments).

#include "uavip/core/types.h"

#include <string>
#include <vector>

namespace uavip::io {

/// How a cloud file is read (YAML section `input:`).
struct CloudReadOptions {
  /// LAS only: ASPRS classes whose points are dropped (e.g. 3, 4, 5 vegetation, 7 noise).
  std::vector<int> drop_classes;
  /// Every coordinate is multiplied by this to give metres, after a LAS file's own
  /// unit conversion: 0.001 for a cloud in millimetres, 0.01 in centimetres, 0.3048
  /// in international feet. 1 = the file is in metres (or a LAS file says its unit).
  double scale{1.0};
  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "input") const;
};

/// What reading did besides returning points (for the printout and scene.json).
struct CloudReadInfo {
  std::string note;                   ///< one line, e.g. the unit conversion of a LAS file; empty if none
  Vec3 origin_m{Vec3::Zero()};        ///< subtracted from the file's coordinates (after unit conversion) [m]
};

/// Reads a cloud by extension (.pcd, .ply, .las; .xyz, .txt and .csv: x y z first on
/// each line, separated by spaces, tabs or commas, one optional header line of
/// names such as "x,y,z" or "//X Y Z Intensity"; .laz is refused with the command
/// that decompresses it), then applies options.scale. Throws InputError naming the file for a
/// missing or unreadable file, an unknown extension, an empty cloud or a non-finite
/// point (with its index or line).
PointList loadCloud(const std::string& path, const CloudReadOptions& options = {}, CloudReadInfo* info = nullptr);

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
