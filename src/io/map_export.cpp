#include "uavip/io/map_export.h"

#include <cmath>
#include <sstream>

#include "uavip/core/text.h"
#include "uavip/io/wpml_export.h"

namespace uavip::io {
namespace {

/// "lon,lat,alt" of KML, alt above EGM96.
std::string kmlCoordinate(const Georeference& geo, const Geodetic& g) {
  return formatFixed(g.lon_deg, 9) + "," + formatFixed(g.lat_deg, 9) + "," +
         formatFixed(geo.egm96Height(g), 3);
}

/// v rounded to `decimals` places (JSON numbers as written).
double geoRounded(double v, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(v * scale) / scale;
}

std::string sortieName(const Flight& f) {
  if (f.sortie > 0)
    return (f.uav > 0 ? "uav " + std::to_string(f.uav) + " " : "") + "sortie " +
           std::to_string(f.sortie);
  std::string ids;
  for (int id : f.surface_ids) ids += (ids.empty() ? "" : ",") + std::to_string(id);
  return "surface " + ids;
}

}  // namespace

std::string flightsKml(const std::vector<Flight>& flights, const Georeference& geo,
                       const Vec3& home, const std::string& name) {
  std::ostringstream os;
  os << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
     << "<kml xmlns=\"http://www.opengis.net/kml/2.2\">\n"
     << "  <Document>\n"
     << "    <name>" << markupEscaped(name) << "</name>\n"
     << "    <description>uavip flight; altitudes absolute (above EGM96 mean sea level)"
        "</description>\n"
     << "    <Style id=\"path\"><LineStyle><color>ff00a5ff</color><width>3</width></LineStyle>"
        "</Style>\n"
     << "    <Style id=\"stop\"><IconStyle><scale>0.6</scale></IconStyle></Style>\n"
     << "    <Placemark>\n      <name>home</name>\n      "
        "<Point><altitudeMode>absolute</altitudeMode>"
     << "<coordinates>" << kmlCoordinate(geo, geo.toGeodetic(home)) << "</coordinates></Point>\n"
     << "    </Placemark>\n";
  for (const Flight& f : flights) {
    os << "    <Folder>\n      <name>" << sortieName(f) << "</name>\n"
       << "      <Placemark>\n        <name>" << sortieName(f) << " path</name>\n"
       << "        <styleUrl>#path</styleUrl>\n"
       << (f.uav > 0 ? "        <ExtendedData><Data name=\"uav\"><value>" + std::to_string(f.uav) +
                           "</value></Data></ExtendedData>\n"
                     : std::string())
       << "        <LineString><altitudeMode>absolute</altitudeMode><coordinates>\n";
    for (const auto& w : f.waypoints)
      os << "          " << kmlCoordinate(geo, geo.toGeodetic(w.enu)) << "\n";
    os << "        </coordinates></LineString>\n      </Placemark>\n";
    for (const auto& w : f.waypoints) {
      if (!w.isStop()) continue;
      const Geodetic g = geo.toGeodetic(w.enu);
      const double heading = headingFromYaw(w.yaw_deg);
      os << "      <Placemark>\n        <name>" << stopId(w) << "</name>\n"
         << "        <styleUrl>#stop</styleUrl>\n"
         << "        <Camera><longitude>" << formatFixed(g.lon_deg, 9) << "</longitude><latitude>"
         << formatFixed(g.lat_deg, 9) << "</latitude><altitude>"
         << formatFixed(geo.egm96Height(g), 3) << "</altitude><heading>" << formatFixed(heading, 2)
         << "</heading><tilt>" << formatFixed(90.0 + w.gimbal_pitch_deg, 2)
         << "</tilt><altitudeMode>absolute</altitudeMode></Camera>\n"
         << "        <ExtendedData><Data name=\"heading_deg\"><value>" << formatFixed(heading, 2)
         << "</value></Data><Data name=\"gimbal_pitch_deg\"><value>"
         << formatFixed(w.gimbal_pitch_deg, 2) << "</value></Data></ExtendedData>\n"
         << "        <Point><altitudeMode>absolute</altitudeMode><coordinates>"
         << kmlCoordinate(geo, g) << "</coordinates></Point>\n      </Placemark>\n";
    }
    os << "    </Folder>\n";
  }
  os << "  </Document>\n</kml>\n";
  return os.str();
}

nlohmann::json flightsGeoJson(const std::vector<Flight>& flights, const Georeference& geo,
                              const Vec3& home, const std::string& name) {
  using nlohmann::json;
  const auto position = [](const Geodetic& g) {
    return json::array(
        {geoRounded(g.lon_deg, 9), geoRounded(g.lat_deg, 9), geoRounded(g.h_ellipsoid_m, 3)});
  };
  const double home_h = geo.toGeodetic(home).h_ellipsoid_m;
  json features = json::array();
  features.push_back(
      {{"type", "Feature"},
       {"geometry", {{"type", "Point"}, {"coordinates", position(geo.toGeodetic(home))}}},
       {"properties", {{"kind", "home"}}}});
  for (const Flight& f : flights) {
    json line = json::array();
    for (const auto& w : f.waypoints) line.push_back(position(geo.toGeodetic(w.enu)));
    features.push_back(
        {{"type", "Feature"},
         {"geometry", {{"type", "LineString"}, {"coordinates", line}}},
         {"properties", {{"kind", "path"}, {"name", sortieName(f)}, {"sortie", f.sortie}}}});
    if (f.uav > 0) features.back()["properties"]["uav"] = f.uav;
    for (const auto& w : f.waypoints) {
      if (!w.isStop()) continue;
      const Geodetic g = geo.toGeodetic(w.enu);
      features.push_back({{"type", "Feature"},
                          {"geometry", {{"type", "Point"}, {"coordinates", position(g)}}},
                          {"properties",
                           {{"kind", "stop"},
                            {"id", stopId(w)},
                            {"sortie", f.sortie},
                            {"surface_id", w.surface_id},
                            {"heading_deg", geoRounded(headingFromYaw(w.yaw_deg), 2)},
                            {"gimbal_pitch_deg", geoRounded(w.gimbal_pitch_deg, 2)},
                            {"height_reference", "WGS84 ellipsoid (RFC 7946)"},
                            {"height_egm96_m", geoRounded(geo.egm96Height(g), 3)},
                            {"height_above_home_m", geoRounded(g.h_ellipsoid_m - home_h, 3)}}}});
    }
  }
  return {{"type", "FeatureCollection"}, {"name", name}, {"features", features}};
}

}  // namespace uavip::io
