#pragma once
/// \file
/// The operator's corrections before the flight (paper §III-B: boundaries of
/// concave surfaces are modified by hand, and the operator confirms every boundary
/// before waypoints are generated). An edits file (YAML, `uavip-edits: 1`) changes the
/// detected scene before stages 6–7: per surface (named by id and fingerprinted by the
/// centroid and normal of its points, so an edit made on another detection is refused)
/// `boundary` (replace), `add` / `cut` polygons, `delete`, `merge`; and `keep_out`
/// volumes (boxes, vertical cylinders) that become solids of the collision world and
/// the planning grid. `uavip plan SCENE --edits FILE`, or `edits: FILE` in a scenario.
/// docs/formats.md "Edits file" has the format.

#include <string>
#include <vector>

#include "uavip/core/types.h"

namespace uavip::app {

struct Config;

/// Tolerances of an edits file's checks.
struct EditsOptions {
  double fingerprint_centroid_m{0.05};  ///< a surface's centroid may differ this much [m]
  double fingerprint_normal_deg{2.0};   ///< and its normal this much [deg]
  double plane_tolerance_m{0.25};       ///< a polygon vertex at most this far off the plane [m]
  double coplanar_deg{5.0};             ///< merged surfaces: normals within this [deg]
  double raster_cell_m{0.05};           ///< add / cut / merge are traced on cells of this edge [m]

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "edits") const;
};

/// One entry of `surfaces:`.
struct SurfaceEdit {
  int line{0};  ///< 1-based line of the entry in its file (0 when built in code)
  int id{0};
  Vec3 centroid{Vec3::Zero()};  ///< fingerprint: the surface's centroid [m]
  Vec3 normal{Vec3::UnitZ()};   ///< fingerprint: its unit normal
  PointList boundary;           ///< replacement outline (scene frame), empty = keep [m]
  std::vector<PointList> add;   ///< polygons added to the surface [m]
  std::vector<PointList> cut;   ///< polygons cut out of it [m]
  bool remove{false};           ///< `delete: true`: the points become an obstacle
  std::vector<int> merge;       ///< ids of coplanar surfaces merged into this one
};

/// One entry of `keep_out:`.
struct KeepOutEdit {
  int line{0};
  KeepOut volume;
};

/// An edits file as read.
struct Edits {
  std::string file;    ///< the file as given (messages)
  std::string sha256;  ///< of its bytes (empty when built in code)
  std::vector<SurfaceEdit> surfaces;
  std::vector<KeepOutEdit> keep_out;
  EditsOptions options;
};

/// Reads an edits file's text strictly (unknown keys, wrong types, a missing
/// fingerprint, a polygon of fewer than 3 points, a non-positive size: InputError
/// "<file>:<line>: …").
Edits parseEdits(const std::string& yaml_text, const std::string& file);

/// Reads `path` (parseEdits) and records its sha256.
Edits loadEdits(const std::string& path);

/// The YAML text of `edits`: parseEdits(editsYamlText(e)) gives `e` back (coordinates
/// written with 17 significant digits). The file's one writer.
std::string editsYamlText(const Edits& edits);

/// Applies `edits` to `scene` in file order, after checking all of them: each surface
/// edit's id exists and its fingerprint matches; every polygon's vertices lie within
/// plane_tolerance_m of the plane and, projected, form a simple polygon; a merge joins
/// coplanar surfaces only. Returns one line per applied edit ("surfaces[0] (line 4):
/// surface 2 boundary replaced, 6 vertices, 18.0 → 16.5 m²"). Throws InputError
/// "<file>:<line>: surfaces[i]: …" naming the edit and why; `scene` is then untouched.
std::vector<std::string> applyEdits(Scene& scene, const Edits& edits);

/// Checks the keep-out volumes of `scene` against the plan `config` asks for: none may
/// contain `mission.home` or `mission.start`, nor every photo stop of one of the
/// surfaces `surface_ids` (stage 6 with `config.coverage`). Throws InputError naming
/// the file, the keep-out and why.
void checkKeepOuts(const Scene& scene, const Config& config, const std::vector<int>& surface_ids,
                   const Edits& edits);

}  // namespace uavip::app
