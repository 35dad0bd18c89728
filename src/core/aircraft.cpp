#include "uavip/core/aircraft.h"

#include "uavip/core/error.h"
#include "uavip/core/text.h"

namespace uavip::aircraft {
namespace {

// Cameras: the wide (mapping) camera of each data sheet. Where a sheet gives the
// sensor format and the 35 mm equivalent focal length only, the sensor size is the
// format's nominal size and f = f_35 · sensor diagonal / 43.27 mm (docs/formats.md).
constexpr CameraSpec kH20Wide{6.17, 4.55, 4.5, 4056, 3040};       // 1/2.3", 12 MP, DFOV 82.9°
constexpr CameraSpec kH20nWide{5.37, 3.02, 4.36, 1920, 1080};     // 1/2.7" starlight, DFOV 70.5°
constexpr CameraSpec kH30Wide{9.7, 7.3, 6.72, 8064, 6048};        // 1/1.3", 48 MP, 24 mm eq.
constexpr CameraSpec kM30Wide{6.4, 4.8, 4.5, 4000, 3000};         // 1/2", 12 MP, DFOV 84°
constexpr CameraSpec kFourThirds{17.3, 13.0, 12.29, 5280, 3956};  // 4/3", 20 MP, 24 mm eq.
constexpr CameraSpec kM3tWide{6.4, 4.8, 4.4, 8000, 6000};         // 1/2", 48 MP, 24 mm eq.
constexpr CameraSpec kM4tWide{9.7, 7.3, 6.72, 8064, 6048};        // 1/1.3", 48 MP, 24 mm eq.

// Seconds in a minute, for hover times the sheets give in minutes.
constexpr double kMin = 60.0;

}  // namespace

const std::vector<Payload>& payloads() {
  // Cloud API camera enumeration; pitch: PSDK "Gimbal Management" (mounted below).
  static const std::vector<Payload> list = {
      {"h20", "Zenmuse H20", 42, -120.0, 45.0, kH20Wide},
      {"h20t", "Zenmuse H20T", 43, -120.0, 30.0, kH20Wide},
      {"h20n", "Zenmuse H20N", 61, -120.0, 30.0, kH20nWide},
      {"h30", "Zenmuse H30", 82, -120.0, 60.0, kH30Wide},
      {"h30t", "Zenmuse H30T", 83, -120.0, 60.0, kH30Wide},
      // The H20 on the M300/M350 upper gimbal port (PSDK dual-gimbal, mounted on
      // top): it looks up to the zenith, for bridge decks and ceilings.
      {"h20-up", "Zenmuse H20 (upper gimbal)", 42, -30.0, 90.0, kH20Wide, 2},
  };
  return list;
}

namespace {

/// A profile from its figures; `payload` is its camera (built in, or the default one).
Profile aircraftOf(const char* name, const char* model, int drone_enum, int sub_enum, bool built_in,
                   const Payload& payload, double speed_mps, double hover_min, double span_m,
                   double height_m) {
  Profile p;
  p.name = name;
  p.model = model;
  p.drone_enum = drone_enum;
  p.drone_sub_enum = sub_enum;
  p.take_off_ref_point = built_in;  // documented for the models with their own camera
  p.built_in_camera = built_in;
  p.payload = payload;
  p.max_speed_mps = speed_mps;
  p.hover_time_s = hover_min * kMin;
  p.span_m = span_m;
  p.height_m = height_m;
  return p;
}

}  // namespace

const std::vector<Profile>& profiles() {
  // Aircraft: DJI Cloud API "Product Support" enumerations; speed, hover time [min] and
  // size [m] from each aircraft's published specifications (docs/formats.md).
  const Payload& h20 = payloads()[0];
  static const std::vector<Profile> list = {
      aircraftOf("generic", "generic UAV (the config's own figures)", 0, 0, true,
                 {"generic", "the config's camera", 0, -90.0, 90.0, {}}, 0.0, 0.0, 0.0, 0.0),
      aircraftOf("m300", "Matrice 300 RTK", 60, 0, false, h20, 23.0, 55, 1.43, 0.43),
      aircraftOf("m350", "Matrice 350 RTK", 89, 0, false, h20, 23.0, 53, 1.43, 0.43),
      aircraftOf("m30", "Matrice 30", 67, 0, true,
                 {"m30", "M30 Camera", 52, -120.0, 45.0, kM30Wide}, 23.0, 36, 1.09, 0.22),
      aircraftOf("m30t", "Matrice 30T", 67, 1, true,
                 {"m30t", "M30T Camera", 53, -120.0, 45.0, kM30Wide}, 23.0, 36, 1.09, 0.22),
      aircraftOf("m3e", "Mavic 3 Enterprise (M3E)", 77, 0, true,
                 {"m3e", "Mavic 3E Camera", 66, -90.0, 35.0, kFourThirds}, 15.0, 38, 0.62, 0.11),
      aircraftOf("m3t", "Mavic 3 Thermal (M3T)", 77, 1, true,
                 {"m3t", "Mavic 3T Camera", 67, -90.0, 35.0, kM3tWide}, 15.0, 38, 0.62, 0.11),
      aircraftOf("m4e", "Matrice 4E", 99, 0, true,
                 {"m4e", "M4E Camera", 88, -90.0, 35.0, kFourThirds}, 21.0, 42, 0.71, 0.15),
      aircraftOf("m4t", "Matrice 4T", 99, 1, true, {"m4t", "M4T Camera", 89, -90.0, 35.0, kM4tWide},
                 21.0, 42, 0.71, 0.15),
  };
  return list;
}

std::string profileList() {
  std::string out;
  for (const Profile& d : profiles()) {
    out += (out.empty() ? "" : ", ") + d.name + " (" + d.model;
    if (!d.isGeneric()) {
      out += ", " + d.payload.model + ", pitch " + formatNumber(d.payload.pitch_min_deg) + ".." +
             formatNumber(d.payload.pitch_max_deg);
    }
    out += ")";
  }
  return out;
}

std::string payloadList() {
  std::string out;
  for (const Payload& p : payloads()) out += (out.empty() ? "" : ", ") + p.name;
  return out;
}

Profile findProfile(const std::string& name, const std::string& payload, const std::string& what) {
  for (const Profile& d : profiles()) {
    if (d.name != name) continue;
    if (payload.empty()) return d;
    if (d.built_in_camera) {
      throw InputError(what + ": the " + d.model + " has its own camera (" + d.payload.model +
                       "); --payload is for the m300 and m350 (" + payloadList() + ")");
    }
    for (const Payload& p : payloads()) {
      if (p.name != payload) continue;
      Profile out = d;
      out.payload = p;
      return out;
    }
    throw InputError("--payload: unknown camera '" + payload + "'; one of " + payloadList());
  }
  std::string names;
  for (const Profile& d : profiles()) names += (names.empty() ? "" : ", ") + d.name;
  throw InputError(what + ": unknown aircraft '" + name + "'; one of " + names);
}

}  // namespace uavip::aircraft
