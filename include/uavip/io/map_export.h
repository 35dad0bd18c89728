#pragma once
/// \file
/// The flight on a map before going to the site (docs/formats.md, "KML and GeoJSON"):
///  - KML 2.2 for Google Earth: one Folder per sortie with the path as a LineString
///    (altitudeMode absolute: heights above EGM96, which is what Google Earth's
///    absolute altitudes are) and each photo stop a Placemark whose Camera looks
///    along the stop's heading and tilt (tilt = 90° + gimbal pitch: 0 looks down),
///    home as a Placemark;
///  - GeoJSON (RFC 7946): the path of each sortie a LineString with [lon, lat, h]
///    where h is the height above the WGS84 ellipsoid (RFC 7946 §4), each stop a
///    Point with id, sortie, heading, pitch and the heights in its properties.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "uavip/io/geodesy.h"
#include "uavip/io/mission_export.h"

namespace uavip::io {

/// The KML document of the flights; `home` is the take-off point (local) [m].
std::string flightsKml(const std::vector<Flight>& flights, const Georeference& geo,
                       const Vec3& home, const std::string& name);

/// The GeoJSON FeatureCollection of the flights.
nlohmann::json flightsGeoJson(const std::vector<Flight>& flights, const Georeference& geo,
                              const Vec3& home, const std::string& name);

}  // namespace uavip::io
