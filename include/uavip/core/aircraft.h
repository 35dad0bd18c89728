#pragma once
/// \file
/// Aircraft profiles: a drone and the camera it carries, with the makers' published
/// figures that decide a plan (camera → GSD and footprint, gimbal pitch range, speed,
/// hover time, span with propellers → inflation) and the enumerations DJI's WPML
/// names them by. The one table of aircraft: planning reads it through the config's
/// profile layer (app/profile.h), the DJI export through io/wpml_export.h. The
/// sources of every figure: docs/formats.md, "Aircraft profiles".

#include <string>
#include <vector>

namespace uavip::aircraft {

/// A photo camera as its data sheet gives it.
struct CameraSpec {
  double sensor_w_mm{0.0};  ///< sensor width [mm]
  double sensor_h_mm{0.0};  ///< sensor height [mm]
  double focal_mm{0.0};     ///< focal length [mm] (not the 35 mm equivalent)
  int image_w_px{0};        ///< image width [px]
  int image_h_px{0};        ///< image height [px]
};

/// A camera a drone carries: the built-in one or a gimbal payload.
struct Payload {
  std::string name;             ///< `--payload` value, e.g. "h30"
  std::string model;            ///< "Zenmuse H30"
  int payload_enum{0};          ///< wpml:payloadEnumValue (0: none, not a DJI camera)
  double pitch_min_deg{-90.0};  ///< lowest gimbal pitch, up positive [deg]
  double pitch_max_deg{30.0};   ///< highest gimbal pitch, up positive [deg]
  CameraSpec camera;            ///< the camera the plan's photos are taken with
  int position_index{0};        ///< wpml:payloadPositionIndex (0 main gimbal, 2 upper port)
};

/// A drone with its payload.
struct Profile {
  std::string name;               ///< `--drone` / `uav.model` value, e.g. "m350"
  std::string model;              ///< "Matrice 350 RTK"
  int drone_enum{0};              ///< wpml:droneEnumValue (0: not a DJI aircraft)
  int drone_sub_enum{0};          ///< wpml:droneSubEnumValue
  bool take_off_ref_point{true};  ///< wpml:takeOffRefPoint is documented for the model
  bool built_in_camera{true};     ///< false: takes the payloads of payloads()
  Payload payload;                ///< the camera it carries (its default, or --payload)
  double max_speed_mps{0.0};      ///< the maker's maximum horizontal speed [m/s]
  double hover_time_s{0.0};       ///< the maker's maximum hover time [s]
  double span_m{0.0};             ///< largest width with propellers unfolded [m]
  double height_m{0.0};           ///< height with the payload [m]

  /// The part of the hover time a plan may use: 80 % of the published figure [s]
  /// (the flight model's reserve comes on top).
  double enduranceS() const { return 0.8 * hover_time_s; }
  /// True for `generic`, the profile that sets nothing (today's behaviour).
  bool isGeneric() const { return name == "generic"; }
};

/// A gimbal pitch is within a range when it lies at most this far outside [deg]; the
/// planner and the DJI export judge with the same tolerance.
constexpr double kPitchToleranceDeg = 1e-6;

/// True when `pitch_deg` is within [min_deg, max_deg] (kPitchToleranceDeg).
inline bool pitchWithin(double pitch_deg, double min_deg, double max_deg) {
  return pitch_deg >= min_deg - kPitchToleranceDeg && pitch_deg <= max_deg + kPitchToleranceDeg;
}

/// Every profile `--drone` and `uav.model` take, in the order `--help` lists them.
const std::vector<Profile>& profiles();
/// The cameras `--payload` puts on a drone without a built-in camera.
const std::vector<Payload>& payloads();
/// The profile named `name` (with `payload`, "" for its default camera); throws
/// InputError naming the value and listing the names (prefix `what`, e.g. "--drone").
Profile findProfile(const std::string& name, const std::string& payload = "",
                    const std::string& what = "--drone");
/// "m300 (Matrice 300 RTK, Zenmuse H20, pitch -120..45), …": for --help and errors.
std::string profileList();
/// "h20, h20t, …": the payload names.
std::string payloadList();

}  // namespace uavip::aircraft
