#pragma once
/// \file
/// Point cloud files: PCD and PLY (PCL readers/writers) and XYZ text
/// ("x y z" per line, extra columns ignored, '#' comments).

#include "uavip/core/types.h"

#include <string>

namespace uavip::io {

/// Reads a cloud by extension (.pcd, .ply, .xyz, .txt). Throws InputError naming
/// the file for a missing or unreadable file, an unknown extension, an empty cloud
/// or a non-finite point (with its index or line).
PointList loadCloud(const std::string& path);

/// Writes a binary PCD atomically (temporary file + rename). Throws std::runtime_error on I/O failure.
void saveCloudPcd(const std::string& path, const PointList& cloud);

}  // namespace uavip::io
