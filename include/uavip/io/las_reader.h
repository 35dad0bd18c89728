#pragma once
/// \file
/// Reader of ASPRS LAS files (airborne and terrestrial laser scans), written from the
/// ASPRS LAS 1.0–1.4 specifications; no PDAL or LASzip. Uncompressed LAS 1.0–1.4,
/// point data formats 0–10. Coordinates come out in metres, recentred near the
/// origin so that they keep their precision as doubles in the pipeline's local frame.
///
/// Units: LAS stores integers X, Y, Z; a file coordinate is X × scale + offset, in
/// the linear unit of the file's coordinate reference system (CRS). The unit is read
/// from the LASF_Projection records (VLRs, and EVLRs of LAS 1.4), in this order:
///   1. OGC WKT (record 2112): the linear UNIT of the projected CRS (PROJCS; WKT2:
///      PROJCRS, LENGTHUNIT) for x,y; the unit of a VERT_CS (VERTCRS) for z, if any;
///   2. GeoTIFF keys (record 34735): 3076 ProjLinearUnitsGeoKey for x,y, 4099
///      VerticalUnitsGeoKey for z (EPSG codes 9001 metre, 9002 international foot,
///      9003 US survey foot; 32767 with 3077 ProjLinearUnitSizeGeoKey for x,y);
///   3. nothing: metres assumed.
/// z takes the horizontal unit when no vertical unit is given. A geographic CRS
/// (longitude/latitude in degrees) cannot be turned into metres by a factor and is
/// rejected. Only the unit is interpreted: no reprojection, no datum handling.
///
/// Thread safety: readLas has no shared state; concurrent calls are safe.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "uavip/core/types.h"

namespace uavip::io {

/// Options of the LAS reader.
struct LasOptions {
  /// ASPRS classification codes whose points are skipped (e.g. 3, 4, 5 vegetation,
  /// 7 noise, 18 high noise). Each must be in 0..255.
  std::vector<int> drop_classes;

  /// Throws InputError "<where>: drop_classes ..." for a code outside 0..255.
  void validate(const std::string& where = "las") const;
};

/// A LAS file read into metres, recentred.
struct LasCloud {
  /// Kept points [m]: file coordinates (scale and offset applied) × unit_to_m (x, y)
  /// or × z_unit_to_m (z), minus origin_m.
  PointList points;
  /// ASPRS class per kept point, parallel to points (formats 0–5: the low 5 bits of
  /// the classification byte; formats 6–10: the 8-bit class field).
  std::vector<std::uint8_t> classification;
  /// Subtracted from every point [m, in the file's CRS]: x, y = centre of the header
  /// bounds (or of the points, if the header bounds are not finite or min > max)
  /// rounded to whole metres; z = 0 (elevations kept) unless the z bounds lie beyond
  /// 10 km (io::recentringOrigin, the rule of every cloud reader).
  Vec3 origin_m{Vec3::Zero()};
  double unit_to_m{1.0};  ///< metres per file unit of x and y [m]
  /// "metre", "international foot", "US survey foot" (else the WKT's name).
  std::string unit_name{"metre"};
  /// Where the x,y unit came from: "WKT", "GeoTIFF key 3076 (ProjLinearUnitsGeoKey)",
  /// "GeoTIFF keys 3076/3077 (user-defined unit size)" or "none in file (metres
  /// assumed)" (possibly with a note, e.g. an EPSG code that was not resolved).
  std::string unit_source;
  double z_unit_to_m{1.0};           ///< metres per file unit of z [m]
  std::string z_unit_name{"metre"};  ///< as unit_name, for z
  /// Where the z unit came from: "WKT VERT_CS", "GeoTIFF key 4099 (VerticalUnitsGeoKey)",
  /// "horizontal unit" (none given for z) or "none in file (metres assumed)".
  std::string z_unit_source;
  /// The file's coordinate reference system as PROJ reads it: the OGC WKT of record
  /// 2112, else "EPSG:P" (GeoTIFF key 3072 ProjectedCSTypeGeoKey) with "+V" for key
  /// 4096 VerticalCSTypeGeoKey; empty when the file states none.
  std::string crs;
  std::string crs_source;  ///< where crs came from, e.g. "LAS WKT record 2112"; empty if none
  int version_major{1};
  int version_minor{0};
  int point_format{0};  ///< 0..10
  /// Bytes per point record (≥ the format's size; extra bytes ignored).
  int point_record_length{0};
  std::uint64_t points_in_file{0};  ///< point count from the header
  std::size_t dropped{0};           ///< points skipped by drop_classes
};

/// Reads an uncompressed LAS 1.0–1.4 file, point formats 0–10, into metres.
///
/// Throws InputError "<path>: <what>, <what to do>" (one line) for: a .laz path or a
/// compressed point format (bit 7 or 6 of the format byte set; names `laszip -i x.laz
/// -o x.las` (LAStools) and `pdal translate x.laz x.las`), a missing, unreadable or
/// non-regular file, a bad signature, an unsupported version, a header size smaller
/// than the version requires, an offset to the point data inside the header or past
/// the end, VLRs/EVLRs that overrun their space, an unknown point format, a point
/// record length shorter than the format needs, a point count beyond the file size
/// (checked before anything is allocated), zero points, more than 2^31 points, a
/// non-finite or zero scale factor or a non-finite offset, a malformed WKT or
/// GeoKeyDirectory, an unsupported unit code, a geographic CRS, and a bad
/// LasOptions. All points dropped by drop_classes is not an error (empty points).
LasCloud readLas(const std::string& path, const LasOptions& options = {});

/// Receives one chunk of kept points [m, recentred] and their ASPRS classes (parallel).
using LasChunkSink =
    std::function<void(const PointList& points, const std::vector<std::uint8_t>& classes)>;

/// readLas without holding the points: hands them to `sink` in chunks of at most
/// 256 KiB of records, in file order, already in metres and recentred (origin_m is
/// known before the first chunk: from the header bounds, else from one pass more over
/// the points). The returned LasCloud has every field but `points` and
/// `classification`. `on_header`, if set, sees that header information (origin_m
/// included) before the first chunk. Same errors as readLas; memory does not grow
/// with the file.
LasCloud streamLas(const std::string& path, const LasOptions& options, const LasChunkSink& sink,
                   const std::function<void(const LasCloud&)>& on_header = {});

/// True if the path ends in ".las" (case-insensitive). ".laz" is not LAS.
bool isLasPath(const std::string& path);

}  // namespace uavip::io
