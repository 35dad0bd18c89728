#pragma once
/// \file
/// OUT/mission.html: one self-contained HTML page per mission that any
/// browser opens offline. It embeds three.js r111 (Debian libjs-three, compiled into
/// the binary: nothing is read at run time), the page's own script, and the data:
///  - the clean cloud, evenly decimated to MissionPageOptions::max_cloud_points, each
///    point with its class (surface / obstacle / other) and surface;
///  - the surfaces' boundaries with id and mission status;
///  - every photo stop (position, yaw, gimbal pitch, surface, index, target);
///  - the flight per sortie (or each surface's own path without a flight), resampled
///    along its segments with the clearance to the nearest cloud point at each sample;
///  - with a fleet of two or more UAVs (mission.json `fleet`): each UAV's sorties in its
///    colour, and each UAV's motion (io::recordedFleetMotion) for the time slider, which
///    shows every UAV at the slider's time and the exact closest approach between two
///    airborne UAVs so far (docs/fleet.md, "The 3D page"). Hash `t=SECONDS` sets it; the
///    state has data-fleet-t, data-fleet-positions and data-fleet-closest.
/// Positions are quantised to 16 bits per axis over the box of everything drawn
/// (bridge: 1.5 mm a step over 100 m) and inlined as base64, never as JSON numbers.
/// A JSON block `<script type="application/json" id="uavip-summary">` holds the counts
/// (photos, waypoints, sorties, …) for tests and tools.
/// The page draws an even subsample of about 40,000 of the stored cloud points (what
/// a software renderer draws in a frame; all of them on request). It sets
/// document.title to "ready" once drawn (or to "error: …") and publishes its camera in
/// the data-* attributes of #uavip-state (data-matrix: projection × view, column-major,
/// of positions minus data-origin; data-canvas; data-frame-ms; data-ready-ms). The URL
/// hash chooses: `view=top|front|side|orbit`, `layers=cloud,flight` (the layers shown, of
/// cloud, boundaries, labels, photos, flight, home, order), `path=sortie|clearance` (the
/// path's colouring), `points=all`, `canvas=WxH` (a fixed drawing size in CSS pixels).
/// Edit mode (`src/view/mission_edit.js`, a script of its own that uses only
/// what the page exposes as `window.uavipPage`): pick a surface, drag, insert and remove
/// its boundary vertices in its plane, delete or merge surfaces, add keep-out boxes;
/// "Save edits" downloads edits.yaml (app/edits.h) and shows the `uavip plan … --edits`
/// command. Test hook: hash `edit=S:V:DX:DY` drags vertex V of surface S by (DX, DY)
/// CSS pixels with pointer events and saves (#edit-yaml; data-edit-* of #uavip-state).
/// Deterministic: the same scene and mission give the same bytes.

#include <cstddef>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/io/geodesy.h"
#include "uavip/planning/fleet_types.h"
#include "uavip/planning/types.h"

namespace uavip::view {

/// Options of the mission page.
struct MissionPageOptions {
  std::string title{"uavip mission"};    ///< heading and <title> until the page is ready
  std::size_t max_cloud_points{300000};  ///< cloud points drawn (evenly subsampled above this)
  /// Samples of all paths together for the clearance colouring.
  std::size_t max_path_samples{40000};
  /// Required clearance for the path colouring [m]; NaN: the mission's
  /// inflation_radius_m, else 1 m.
  double clearance_m{std::numeric_limits<double>::quiet_NaN()};
  /// The scene's CRS in closed form (io::fitGeoreference): a picked point also shows
  /// its latitude, longitude and ellipsoidal height. None: local metres only.
  std::optional<io::GeoFit> geo;
  /// Throws InputError naming a bad value.
  void validate() const;
};

/// The page for a scene and a recorded mission: `mission` is a mission.json document
/// (io/mission_json.h), read strictly by missionFromJson (errors name `mission_path`),
/// or null for the scene alone (detect). A scene without points gives a page without a
/// cloud (run on a scene where nothing was detected); `uavip view` refuses such a scene.
std::string missionPage(const Scene& scene, const nlohmann::json* mission,
                        const MissionPageOptions& options = {},
                        const std::string& mission_path = "mission.json");

/// The page for the planner's results, as `run` and `plan` write them (the mission is
/// the document mission.json holds). `flight` may be null (no ordered flight), and so
/// may `fleet` (a single UAV).
std::string missionPage(const Scene& scene, const std::vector<planning::SurfaceMission>& missions,
                        const planning::FlightPlan* flight, const MissionPageOptions& options = {},
                        const planning::FleetPlan* fleet = nullptr);

/// The three.js r111 library text compiled into the binary (three.min.js followed by
/// examples/js/controls/OrbitControls.js), for tests.
const std::string& embeddedThreeJs();

}  // namespace uavip::view
