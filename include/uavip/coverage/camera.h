#pragma once
/// \file
/// Camera model of the flight strategy (paper §II-F; formulas of QGroundControl's
/// CameraCalc, docs/formats.md): footprint given directly, or from
/// sensor size, focal length, image size and a required ground sample distance.
/// Below it, the camera models the coverage evaluator projects with
/// (coverage_evaluator.h): FootprintCamera (that camera as a frustum) and
/// PinholeCamera.
///
/// Camera frame (2-DOF mount, no roll; the conventions of flight_strategy.cpp):
/// yaw y counter-clockwise from +x (east), gimbal pitch p up positive (−90 = straight
/// down), world ENU metres with z up:
///   forward f = (cos p·cos y, cos p·sin y, sin p),
///   right   r = (sin y, −cos y, 0)   (image width axis, horizontal),
///   up      u = r × f                (image height axis, "up" in the photo).
/// Camera coordinates of a world point q: x = r·(q − c) (right), y = −u·(q − c)
/// (down, as in OpenCV), z = f·(q − c) (depth). With this, a flight-strategy Stop
/// (yaw_deg, gimbal_pitch_deg) images its footprint with the width along axis_w and
/// the height along axis_h.

#include <string>

#include "uavip/core/math.h"
#include "uavip/core/params.h"
#include "uavip/core/types.h"

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
  /// The keys of `camera:` (core/params.h). A sensor key (sensor_mm, focal_mm, and
  /// image_px or gsd_mm_per_px without fx/fy/cx/cy) sets from_sensor, a pinhole key
  /// (fx, fy, cx, cy) sets pinhole; a model's keys read as unset under another model.
  static const params::Table<Camera>& table();
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

/// A camera pose: position [m], yaw [deg], gimbal pitch [deg] (as Stop in
/// flight_strategy.h: yaw counter-clockwise from +x, pitch up positive, −90 = down).
struct ViewPose {
  Vec3 position{Vec3::Zero()};  ///< camera centre [m]
  double yaw_deg{0.0};          ///< heading, counter-clockwise from +x (east) [deg]
  double pitch_deg{0.0};        ///< gimbal pitch, up positive, 0 = horizontal [deg]
};

/// The orthonormal camera frame of a pose (see the file comment); right × up = −forward.
struct ViewFrame {
  ViewPose pose;                ///< the pose it was made from
  Vec3 forward{Vec3::UnitX()};  ///< optical axis (unit)
  Vec3 right{-Vec3::UnitY()};   ///< image width axis, horizontal (unit)
  Vec3 up{Vec3::UnitZ()};       ///< image height axis, "up" in the photo (unit)
};

/// Frame of a pose: f = (cos p cos y, cos p sin y, sin p), r = (sin y, −cos y, 0), u = r × f.
ViewFrame makeViewFrame(const ViewPose& pose);

/// What a camera sees of one world point from one pose.
struct Projection {
  bool in_image{false};  ///< in front of the camera and inside the image (edges included)
  double range_m{0.0};   ///< |point − camera| [m]
  /// GSD at that point [mm/px]: range·1000 / focal_px. Exact for a patch facing the
  /// camera on the optical axis; an upper bound off axis (the local GSD there is
  /// range·cos θ/f tangentially, range·cos²θ/f radially) and for a fronto-parallel
  /// patch (depth ≤ range). Incidence is a separate criterion.
  double gsd_mm_per_px{0.0};
};

/// A camera model. Implementations are immutable after construction and their const
/// members are thread-safe (evaluateCoverage calls them from several threads).
class CameraModel {
 public:
  virtual ~CameraModel() = default;

  /// Projection of world point `point` [m] seen from `pose`.
  virtual Projection project(const ViewPose& pose, const Vec3& point) const = 0;

  /// The same from a prepared frame (makeViewFrame(frame.pose)); evaluateCoverage
  /// calls this once per (view, point) pair so the trigonometry is done once per
  /// view. The default forwards to project(frame.pose, point); override for speed.
  virtual Projection projectInFrame(const ViewFrame& frame, const Vec3& point) const {
    return project(frame.pose, point);
  }

  /// Farthest range at which a point still counts as imaged [m]: the range where the
  /// GSD reaches `max_gsd_mm_per_px` (0 = no GSD limit), capped by the model's own
  /// range limit; +infinity when neither applies. Throws InputError for a negative
  /// or non-finite GSD.
  virtual double maxRange(double max_gsd_mm_per_px) const = 0;

  /// Largest angle between the optical axis and the direction of any point in the
  /// image [rad]; π when the model does not say (evaluations then cull by range only).
  virtual double maxOffAxisRad() const { return kPi; }
};

/// Options of FootprintCamera.
struct FootprintCameraOptions {
  Camera camera;            ///< footprint (paper: 0.6 × 0.4 m) or sensor description
  double standoff_m{1.5};   ///< standoff when the camera gives its footprint directly [m] (as
                            ///< CoverageOptions::standoff_m)
  double range_slack{1.5};  ///< the model's own range limit = standoff × range_slack (≥ 1)
  /// Pixels across the footprint width assumed for a camera given by its footprint
  /// only (it has no pixels): focal_px = assumed_image_w_px·standoff / footprint_w,
  /// so the GSD at the standoff is footprint_w·1000 / assumed_image_w_px [mm/px]
  /// (0.6 mm/px for the paper's 0.6 m photo). Ignored for a sensor camera.
  int assumed_image_w_px{1000};

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "footprint_camera") const;
};

/// A central camera: one focal length for the GSD (range·1000 / focal_px) and a
/// projection done in the view's frame (project() makes the frame and forwards).
class CentralCamera : public CameraModel {
 public:
  Projection project(const ViewPose& pose, const Vec3& point) const final;
  double focalPx() const { return focal_px_; }  ///< focal length of the GSD rule [px]

 protected:
  /// r [m] capped by the range where the GSD reaches max_gsd_mm_per_px (0 = no cap);
  /// throws InputError, naming `where`, for a negative or non-finite GSD.
  double cappedRange(double r, double max_gsd_mm_per_px, const std::string& where) const;

  double focal_px_{0.0};  ///< [px]
};

/// The flight strategy's camera (paper §II-F): a frustum whose footprint at the
/// standoff D is footprint_w × footprint_h (solveCamera), i.e. a point is in the
/// image when z > 0, |x| ≤ z·footprint_w/(2D) and |y| ≤ z·footprint_h/(2D).
/// GSD rule: with a sensor, focal_px = min(Iw·f/Sw, Ih·f/Sh) (the GSD is met on both
/// axes, as in solveCamera); with a direct footprint, the equivalent focal length of
/// FootprintCameraOptions::assumed_image_w_px. Own range limit: D × range_slack.
/// Immutable; thread-safe.
class FootprintCamera final : public CentralCamera {
 public:
  /// Validates the options (InputError) and solves the camera.
  explicit FootprintCamera(const FootprintCameraOptions& options);

  Projection projectInFrame(const ViewFrame& frame, const Vec3& point) const override;
  double maxRange(double max_gsd_mm_per_px) const override;
  /// atan of the half footprint's diagonal over the standoff.
  double maxOffAxisRad() const override;
  const CameraGeometry& geometry() const { return geometry_; }  ///< footprint and standoff

 private:
  FootprintCameraOptions options_;
  CameraGeometry geometry_;
  double tan_half_w_{0.0};  ///< footprint_w / (2·standoff)
  double tan_half_h_{0.0};  ///< footprint_h / (2·standoff)
};

/// Intrinsics of a pinhole camera (defaults: FC-Planner's 640 × 480 camera).
/// Pixel coordinates u = cx + fx·x/z, v = cy + fy·y/z (x right, y down, z depth);
/// the image is the closed rectangle 0 ≤ u ≤ width, 0 ≤ v ≤ height, so the
/// horizontal half field of view to the right is atan((width − cx)/fx).
struct PinholeIntrinsics {
  int width_px{640};        ///< image width [px]
  int height_px{480};       ///< image height [px]
  double fx_px{417.0467};   ///< focal length along the width [px]
  double fy_px{461.0951};   ///< focal length along the height [px]
  double cx_px{320.0};      ///< principal point [px]
  double cy_px{240.0};      ///< principal point [px]
  double max_range_m{0.0};  ///< the model's own range limit [m]; 0 = none

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "pinhole") const;
};

/// Pinhole camera. GSD = range·1000 / min(fx, fy) (the worse axis). Immutable;
/// thread-safe.
class PinholeCamera final : public CentralCamera {
 public:
  /// Validates the intrinsics (InputError).
  explicit PinholeCamera(const PinholeIntrinsics& intrinsics);

  Projection projectInFrame(const ViewFrame& frame, const Vec3& point) const override;
  double maxRange(double max_gsd_mm_per_px) const override;
  /// atan of the image corner farthest from the principal point, in focal lengths.
  double maxOffAxisRad() const override;
  const PinholeIntrinsics& intrinsics() const { return k_; }

 private:
  PinholeIntrinsics k_;
};

}  // namespace uavip::coverage
