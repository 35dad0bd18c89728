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
  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "input") const;
};

/// What reading did besides returning points (for the printout and scene.json).
struct CloudReadInfo {
  std::string note;                   ///< one line, e.g. the unit conversion of a LAS file; empty if none
  Vec3 origin_m{Vec3::Zero()};        ///< subtracted from the file's coordinates (after unit conversion) [m]
};

/// Reads a cloud by extension (.pcd, .ply, .xyz, .txt, .las; .laz is refused with
/// the command that decompresses it). Throws InputError naming the file for a
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
