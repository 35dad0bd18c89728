#pragma once
/// \file
/// Camera model of the flight strategy (paper §II-F; formulas of QGroundControl's
/// CameraCalc, docs/formats.md): footprint given directly, or from
/// sensor size, focal length, image size and a required ground sample distance.

#include <string>

namespace uavip::coverage {

/// How the camera is described. Either `footprint_*` (direct, as in the paper:
/// 0.6 × 0.4 m) or, when `from_sensor` is true, sensor/focal/image/GSD.
struct Camera {
  double footprint_w_m{0.6};  ///< photo width on the surface (image x axis) [m]
  double footprint_h_m{0.4};  ///< photo height on the surface (image y axis) [m]

  bool from_sensor{false};
  /// A pinhole camera (YAML fx, fy, cx, cy, image_px): intrinsics in pixels. Its
  /// standoff is the one its gsd_mm_per_px implies (D = GSD·min(fx, fy)/1000), else
  /// the standoff asked for; footprint D·Iw/fx × D·Ih/fy.
  bool pinhole{false};
  double fx_px{0.0};          ///< focal length along the image width [px]
  double fy_px{0.0};          ///< focal length along the image height [px]
  double cx_px{0.0};          ///< principal point [px], in [0, Iw]
  double cy_px{0.0};          ///< principal point [px], in [0, Ih]
  double sensor_w_mm{0.0};    ///< Sw [mm]
  double sensor_h_mm{0.0};    ///< Sh [mm]
  double focal_mm{0.0};       ///< f [mm]
  int image_w_px{0};          ///< Iw [px]
  int image_h_px{0};          ///< Ih [px]
  double gsd_mm_per_px{0.0};  ///< required GSD, met on both axes [mm/px] (pinhole: 0 = none)
  /// Farthest distance the camera works at (YAML camera.max_range_m) [m]; 0 = not
  /// given, then kMaxStandoffWithoutRangeM bounds the standoff.
  double max_range_m{0.0};

  /// Throws InputError naming the bad field (prefix `where`), including a sensor
  /// camera whose standoff (solveCamera) exceeds maxStandoff().
  void validate(const std::string& where = "camera") const;
  /// The farthest standoff flown: max_range_m, else kMaxStandoffWithoutRangeM [m].
  double maxStandoff() const;
};

/// Farthest standoff of a camera without max_range_m [m]: beyond 1 km no inspection
/// photo is taken (a GSD typed in the wrong unit gives thousands of km).
constexpr double kMaxStandoffWithoutRangeM = 1000.0;

/// What the camera gives at the chosen standoff.
struct CameraGeometry {
  double footprint_w_m{0.0};  ///< [m]
  double footprint_h_m{0.0};  ///< [m]
  double standoff_m{0.0};     ///< distance from the surface [m]
  double gsd_w_mm{
      0.0};  ///< achieved GSD along the image width [mm/px] (0 if footprint given directly)
  double gsd_h_mm{0.0};  ///< achieved GSD along the image height [mm/px]
};

/// Solves the camera. With a direct footprint the standoff is `standoff_m`.
/// With a sensor: D = min(Iw·GSD·f/Sw, Ih·GSD·f/Sh) / 1000 [m] so the GSD is met on
/// both axes; footprint = D·S/f on each axis; achieved GSD = D·1000·S/(I·f).
CameraGeometry solveCamera(const Camera& camera, double standoff_m);

}  // namespace uavip::coverage
