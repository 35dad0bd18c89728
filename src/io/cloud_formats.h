#pragma once
/// \file
/// What the cloud readers of io/ share; private to src/io. One file per format
/// (text_reader.cpp: XYZ, TXT, CSV; pcd_reader.cpp: PCD with LZF; ply_reader.cpp:
/// PLY), the header checks and the x y z of a PCD or PLY blob they share
/// (cloud_blob.cpp), the extent check of every reader (cloud_frame.cpp); cloud_io.cpp
/// picks the reader by the file's extension.

#include <pcl/PCLPointCloud2.h>

#include <cstdint>
#include <functional>
#include <istream>
#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/io/cloud_io.h"

namespace uavip::io {

/// Throws InputError: `path` is a mesh without triangle faces (mesh_sampler.cpp).
[[noreturn]] void throwNoFaces(const std::string& path);

/// The extension of `path` in lower case, with its dot (".ply"); empty if none.
std::string lowerExtension(const std::string& path);

/// Parses an x y z text cloud from `in` line by line, handing each point to `point`
/// (the one parser of .xyz/.txt/.csv; loadCloud and streamCloud use it).
void parseXyz(std::istream& in, const std::string& path,
              const std::function<void(const Vec3&)>& point);

/// Every point of an x y z text file (parseXyz).
PointList loadXyz(const std::string& path);

/// The data of a PCD file (uavip's own reader: PCL's PCDReader crashes on damaged
/// files that pass every header check) as a PCLPointCloud2, after the header checks;
/// `in` is the file opened at its start, `file_size` its size [bytes].
pcl::PCLPointCloud2 readPcd(const std::string& path, std::istream& in, std::uint64_t file_size);

/// The points of an ascii or binary PCD file (as fromBlob of readPcd gives them),
/// read `chunk_points` records at a time and handed to `sink` in file order; false,
/// having read only the header, for binary_compressed (one LZF block: read it whole).
bool streamPcd(const std::string& path, std::istream& in, std::uint64_t file_size,
               std::size_t chunk_points, const std::function<void(const PointList&)>& sink);

/// True when the PCD file's header (checked) says ascii or binary: streamPcd streams it.
bool pcdStreams(const std::string& path, std::istream& in, std::uint64_t file_size);

/// A PLY file read by PCL after uavip's header checks (PCL's reader crashes on some
/// malformed headers); `in` and `file_size` as for readPcd.
pcl::PCLPointCloud2 readPly(const std::string& path, std::istream& in, std::uint64_t file_size);

/// The points of a PLY file (as fromBlob of readPly gives them), read `chunk_points`
/// vertices at a time and handed to `sink` in file order; false, having read only the
/// header, when the file is not streamed (plyStreams).
bool streamPly(const std::string& path, std::istream& in, std::uint64_t file_size,
               std::size_t chunk_points, const std::function<void(const PointList&)>& sink);

/// True when the PLY file's header (checked) lets streamPly stream it: ascii or
/// binary_little_endian, the vertex element first and of scalar properties only, not a
/// sensor frame (`obj_info num_rows` above 1). Others are read whole (readPly).
bool plyStreams(const std::string& path, std::istream& in, std::uint64_t file_size);

/// A header count: a whole number >= 0 (no sign, no fraction), else InputError
/// naming the file, the key and the text.
std::uint64_t headerCount(const std::string& path, const std::string& key, const std::string& text);

/// The header's claim against the bytes that follow it: a file that claims more
/// points than it can hold is refused before anything is allocated.
void checkPayload(const std::string& path, std::uint64_t points, std::uint64_t min_bytes_per_point,
                  std::uint64_t available, const std::string& what);

/// The whitespace-separated words of a header line.
std::vector<std::string> headerWords(const std::string& line);

/// x, y, z of every point of a PCD/PLY blob, in double, any numeric field type.
/// An organized cloud (height > 1, a sensor frame) marks missing returns with NaN:
/// those are skipped. Any other non-finite point is an error naming its index.
PointList fromBlob(const pcl::PCLPointCloud2& blob, const std::string& path);
/// The same for part of a cloud: `organized` as the whole cloud is, `first` the index
/// of the blob's first point in it (messages).
PointList fromBlob(const pcl::PCLPointCloud2& blob, const std::string& path, bool organized,
                   std::uint64_t first);

/// The colours of the points fromBlob keeps (io::loadCloudColours).
PointColours coloursFromBlob(const pcl::PCLPointCloud2& blob);

/// Throws InputError when the cloud spans more than kMaxCloudExtentM on an axis,
/// naming the point farthest (on one axis) from the per-axis median of the cloud:
/// a stray point such as 1e308, or a cloud in the wrong unit. `origin` is added back
/// so that the point is shown as in the file.
void requirePhysicalExtent(const std::string& path, const PointList& points, const Vec3& lo,
                           const Vec3& hi, const Vec3& origin);

}  // namespace uavip::io
