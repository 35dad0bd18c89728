#include "uavip/view/views.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <future>
#include <iomanip>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "uavip/core/geometry.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "uavip/view/mission_page.h"

namespace uavip::view {
namespace {

using render::Color;
using render::LegendEntry;
using render::LegendKind;
using render::Vec2;

/// Exact coordinates as a key (points are copies of cloud points).
using Key = std::array<double, 3>;
Key key(const Vec3& p) { return {p.x(), p.y(), p.z()}; }
struct PlyVertex {
  Vec3 p;
  Color c;
  int kind;
  int surface;
};

/// One of the three orthographic views.
struct View {
  const char* title;
  const char* x_label;
  const char* y_label;
  int u, v;          ///< coordinate indices shown as panel x and y
  int toward, sign;  ///< the viewer looks from sign·(axis `toward`): nearer things are drawn last
};

constexpr std::array<View, 3> kViews{{
    {"Top view (from above)", "x east [m]", "y north [m]", 0, 1, 2, 1},
    {"Front view (from the south)", "x east [m]", "z up [m]", 0, 2, 1, -1},
    {"Side view (from the east)", "y north [m]", "z up [m]", 1, 2, 0, 1},
}};

std::vector<Vec2> project(const PointList& pts, const View& view, std::size_t stride = 1) {
  std::vector<Vec2> out;
  out.reserve(pts.size() / std::max<std::size_t>(stride, 1) + 1);
  for (std::size_t i = 0; i < pts.size(); i += std::max<std::size_t>(stride, 1))
    out.emplace_back(pts[i][view.u], pts[i][view.v]);
  return out;
}

/// "faces south" for a normal near an axis, else its components.
std::string facing(const Vec3& n) {
  static const std::array<const char*, 6> kNames{"east", "west", "north", "south", "up", "down"};
  for (int a = 0; a < 3; ++a) {
    const std::size_t which = 2 * static_cast<std::size_t>(a) + (n[a] < 0.0 ? 1 : 0);
    if (std::abs(n[a]) > 0.95) return std::string("faces ") + kNames[which];
  }
  return "normal (" + formatFixed(n.x(), 2) + ", " + formatFixed(n.y(), 2) + ", " +
         formatFixed(n.z(), 2) + ")";
}

/// The four corners of a stop's photo on the surface plane.
PointList footprint(const coverage::FlightStrategy& s, const coverage::Stop& stop) {
  const Vec3 w = s.axis_w * (s.camera.footprint_w_m / 2.0);
  const Vec3 h = s.axis_h * (s.camera.footprint_h_m / 2.0);
  return {stop.target - w - h, stop.target + w - h, stop.target + w + h, stop.target - w + h};
}

/// Cloud points in neither a surface nor an obstacle.
/// (Sorted keys and binary search: a hash set of the keys was slower.)
PointList otherPoints(const Scene& scene) {
  std::vector<Key> used;
  for (const auto& s : scene.surfaces)
    for (const auto& p : s.inliers) used.push_back(key(p));
  for (const auto& o : scene.obstacles)
    for (const auto& p : o.points) used.push_back(key(p));
  std::sort(used.begin(), used.end());
  PointList out;
  for (const auto& p : scene.cloud)
    if (!std::binary_search(used.begin(), used.end(), key(p))) out.push_back(p);
  return out;
}

const planning::SurfaceMission* missionOf(const std::vector<planning::SurfaceMission>& missions,
                                          int id) {
  for (const auto& m : missions)
    if (m.surface_id == id) return &m;
  return nullptr;
}

}  // namespace

render::Color surfaceColor(int id) { return render::palette(id); }

std::string sceneToPly(const Scene& scene, const std::vector<planning::SurfaceMission>& missions) {
  std::vector<PlyVertex> v;
  for (const auto& s : scene.surfaces)
    for (const auto& p : s.inliers) v.push_back({p, surfaceColor(s.id), 1, s.id});
  for (const auto& o : scene.obstacles)
    for (const auto& p : o.points) v.push_back({p, kObstacleColor, 2, -1});
  for (const auto& p : otherPoints(scene)) v.push_back({p, kCloudColor, 0, -1});
  for (const auto& m : missions)
    for (const auto& s : m.strategy.stops) v.push_back({s.position, kStopColor, 3, m.surface_id});

  std::ostringstream os;
  os << "ply\nformat ascii 1.0\ncomment uavip scene: local ENU metres, z up\n"
     << "comment kind: 0 other cloud point, 1 surface point, 2 obstacle point, 3 photo stop\n"
     << "element vertex " << v.size() << "\n"
     << "property float x\nproperty float y\nproperty float z\n"
     << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
     << "property uchar kind\nproperty int surface\nend_header\n";
  char line[160];
  for (const auto& x : v) {
    std::snprintf(line, sizeof line, "%.4f %.4f %.4f %d %d %d %d %d\n", x.p.x(), x.p.y(), x.p.z(),
                  x.c.red8(), x.c.green8(), x.c.blue8(), x.kind, x.surface);
    os << line;
  }
  return os.str();
}

std::string pathsToObj(const std::vector<planning::SurfaceMission>& missions,
                       const planning::FlightPlan* flight) {
  std::ostringstream os;
  std::size_t next = 1;
  char line[128];
  auto polyline = [&](const std::string& name, const PointList& points) {
    os << "o " << name << "\n";
    for (const auto& p : points) {
      std::snprintf(line, sizeof line, "v %.4f %.4f %.4f\n", p.x(), p.y(), p.z());
      os << line;
    }
    os << "l";
    for (std::size_t i = 0; i < points.size(); ++i) os << " " << next + i;
    os << "\n";
    next += points.size();
  };
  if (flight != nullptr && flight->status == planning::FlightPlan::Status::Ok) {
    os << "# uavip flight, local ENU metres (z up): one polyline per sortie, home to home, in "
          "flight order\n";
    for (std::size_t i = 0; i < flight->sorties.size(); ++i)
      polyline("sortie_" + std::to_string(i + 1), flight->sorties[i].waypoints);
    return os.str();
  }
  os << "# uavip flight paths, local ENU metres (z up): one polyline per surface with a mission\n";
  for (const auto& m : missions) {
    if (m.waypoints.size() >= 2) polyline("surface_" + std::to_string(m.surface_id), m.waypoints);
  }
  return os.str();
}

/// Colour of sortie k (from 0): the categorical palette, darkened so it reads over
/// the surfaces' own colours.
Color sortieColor(std::size_t k) {
  return render::palette(static_cast<int>(k)).mix(render::kBlack, 0.35);
}

const render::Style kHomeStyle{render::kBlack, Color{1.0, 1.0, 1.0},   2.0,
                               false,          render::Marker::Square, 12.0};

/// The ordered flight on one view: each sortie in its colour, home, and the place
/// where each surface is entered numbered in flight order.
void drawFlight(render::Panel& p, const planning::FlightPlan& flight, const View& view) {
  for (std::size_t k = 0; k < flight.sorties.size(); ++k)
    p.polyline(project(flight.sorties[k].waypoints, view), render::lineStyle(sortieColor(k), 1.4));
  int n = 0;
  int current = -1;
  for (const auto& s : flight.sorties) {
    for (const auto& st : s.stops) {
      if (st.surface_id == current) continue;
      current = st.surface_id;
      const auto at = project({s.waypoints[st.waypoint]}, view);
      p.text(at.front(), " " + std::to_string(++n),
             {13.0, render::kBlack, render::Align::Left, true});
    }
  }
  p.markers(project({flight.home}, view), kHomeStyle);
}

namespace {

/// Where the overview's parts go on the canvas [px].
struct OverviewLayout {
  double width{0.0}, height{0.0};  ///< canvas
  double top{84.0};                ///< height of the header above the views
  double gap{10.0};                ///< between the panels and the legend column
  double legend_w{0.0};            ///< width of the legend column
  std::array<std::array<double, 4>, 3>
      views{};  ///< left, top, width, height of each view's panel (kViews order)
};

/// The layout: the top view on the left over the full height, the front and side views
/// stacked to its right, the legend column on the right edge.
OverviewLayout overviewLayout(const OverviewOptions& options) {
  OverviewLayout l;
  l.width = options.width_px;
  l.height = options.height_px;
  l.legend_w = std::min(420.0, 0.22 * l.width);
  const double main_w = 0.48 * (l.width - l.legend_w);
  const double side_w = l.width - l.legend_w - main_w - 3.0 * l.gap;
  const double half_h = (l.height - l.top - 2.0 * l.gap) / 2.0;
  l.views = {{
      {l.gap, l.top, main_w, 2.0 * half_h + l.gap},
      {2.0 * l.gap + main_w, l.top, side_w, half_h},
      {2.0 * l.gap + main_w, l.top + half_h + l.gap, side_w, half_h},
  }};
  return l;
}

/// What the views and the legend show, gathered once for all views.
struct OverviewContent {
  const Scene& scene;
  const std::vector<planning::SurfaceMission>& missions;
  const planning::FlightPlan*
      flight;            ///< the ordered flight when there is one (status ok), else null
  PointList other;       ///< cloud points in no surface and no obstacle
  std::size_t stride;    ///< every stride-th cloud point is drawn (the same in every view)
  double min_spacing_m;  ///< smallest stop spacing of any mission, at most 0.5 [m]
};

/// Gathers the content: the flight if flown, the leftover cloud points, the cloud
/// subsampling stride (options.max_cloud_points) and the smallest stop spacing.
OverviewContent overviewContent(const Scene& scene,
                                const std::vector<planning::SurfaceMission>& missions,
                                const OverviewOptions& options,
                                const planning::FlightPlan* flight) {
  const bool flown = flight != nullptr && flight->status == planning::FlightPlan::Status::Ok;
  const std::size_t total = scene.cloud.size();
  const std::size_t stride = options.max_cloud_points > 0 && total > options.max_cloud_points
                                 ? (total + options.max_cloud_points - 1) / options.max_cloud_points
                                 : 1;
  double min_spacing = 0.5;  // [m]
  for (const auto& m : missions) {
    if (m.strategy.spacing_w_m > 0.0) min_spacing = std::min(min_spacing, m.strategy.spacing_w_m);
    if (m.strategy.spacing_h_m > 0.0) min_spacing = std::min(min_spacing, m.strategy.spacing_h_m);
  }
  return {scene, missions, flown ? flight : nullptr, otherPoints(scene), stride, min_spacing};
}

/// The title and the line of counts (scene, missions, flight) above the views.
void drawHeader(render::Figure& fig, const std::string& title, const OverviewContent& c) {
  std::size_t stops = 0, waypoints = 0, ok = 0;
  double length = 0.0;
  for (const auto& m : c.missions) {
    stops += m.strategy.stops.size();
    waypoints += m.waypoints.size();
    length += m.path_length_m;
    ok += planning::flyable(m.status);
  }
  fig.text(20, 34, title, {22.0, render::kBlack, render::Align::Left, true});
  std::ostringstream sub;
  sub << c.scene.cloud.size() << " cloud points, " << c.scene.surfaces.size() << " surfaces, "
      << c.scene.obstacles.size() << " obstacle clusters  |  " << c.missions.size()
      << " surfaces planned, " << ok << " with a flight: " << stops << " photo stops, " << waypoints
      << " waypoints, " << formatFixed(length, 1) << " m over the surfaces";
  if (c.flight != nullptr) {
    sub << "  |  flight " << formatFixed(c.flight->length_m, 1) << " m, "
        << formatFixed(c.flight->duration_s / 60.0, 1) << " min, " << c.flight->sorties.size()
        << " sortie" << (c.flight->sorties.size() == 1 ? "" : "s");
  }
  sub << "  |  local ENU frame, metres";
  fig.text(20, 62, sub.str(), {14.0, Color::rgb(50, 50, 50)});
}

/// A surface's path is its colour mixed halfway toward this.
const Color kPathDark = render::kBlack;
/// Surface points no flown photo images (mission coverage).
const render::Style kUncoveredStyle{render::kBlack, render::Color{1.0, 0.85, 0.0}, 0.6,
                                    false,          render::Marker::Diamond,       5.0};

/// Marker of the start of a surface's own flight (views without an ordered flight).
render::Style startStyle() {
  return render::markerStyle(render::kBlack, render::Marker::Triangle, 11.0);
}

/// Depth along a view: larger is nearer the viewer [m].
double depth(const View& view, const Vec3& c) { return view.sign * c[view.toward]; }

/// The scene's surfaces far to near along a view (painter's order: near ones stay visible).
std::vector<const Surface*> surfacesFarToNear(const Scene& scene, const View& view) {
  std::vector<const Surface*> surfaces;
  for (const auto& s : scene.surfaces) surfaces.push_back(&s);
  std::stable_sort(surfaces.begin(), surfaces.end(), [&](const Surface* a, const Surface* b) {
    return depth(view, a->centroid) < depth(view, b->centroid);
  });
  return surfaces;
}

/// The missions far to near along a view, by the mean of their stops (depth 0 without stops).
std::vector<const planning::SurfaceMission*> missionsFarToNear(
    const std::vector<planning::SurfaceMission>& missions, const View& view) {
  std::vector<const planning::SurfaceMission*> order;
  order.reserve(missions.size());
  for (const auto& m : missions) order.push_back(&m);
  auto mission_depth = [&](const planning::SurfaceMission* m) {
    Vec3 c = Vec3::Zero();
    for (const auto& st : m->strategy.stops) c += st.position;
    return m->strategy.stops.empty()
               ? 0.0
               : depth(view, c / static_cast<double>(m->strategy.stops.size()));
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](const planning::SurfaceMission* a, const planning::SurfaceMission* b) {
                     return mission_depth(a) < mission_depth(b);
                   });
  return order;
}

/// Size of the stop markers on a view [px]: 0.6 × the smallest stop spacing on screen,
/// within [2.5, 6], so dense grids stay readable. rect: the view's panel [px].
double stopMarkerPx(const OverviewContent& c, const View& view, const std::array<double, 4>& rect) {
  uavip::Aabb box = boundingBox(c.scene.cloud);
  for (const auto& m : c.missions)
    for (const auto& st : m.strategy.stops) box.extend(st.position);
  double px_per_m = 50.0;
  if (!box.empty()) {
    const double du = std::max(box.max[view.u] - box.min[view.u], 1e-3) * 1.1;
    const double dv = std::max(box.max[view.v] - box.min[view.v], 1e-3) * 1.1;
    px_per_m = std::min((rect[2] - 86.0) / du, (rect[3] - 80.0) / dv);
  }
  return std::clamp(0.6 * c.min_spacing_m * px_per_m, 2.5, 6.0);
}

/// The cloud layer: points of no surface or obstacle, then the obstacles' points.
void drawCloudLayer(render::Panel& p, const OverviewContent& c, const View& view) {
  const render::Style other_style{kCloudColor, kCloudColor, 0.0, false, render::Marker::Square,
                                  1.8};
  const render::Style obstacle_style{kObstacleColor, kObstacleColor,         0.0,
                                     false,          render::Marker::Square, 2.2};
  p.markers(project(c.other, view, c.stride), other_style);
  for (const auto& o : c.scene.obstacles)
    p.markers(project(o.points, view, c.stride), obstacle_style);
}

/// A mission's photo footprints, as one translucent path in its surface's colour.
void drawFootprints(render::Panel& p, const planning::SurfaceMission& m, const View& view) {
  const Color mc = surfaceColor(m.surface_id);
  const render::Style fp =
      render::patchStyle(mc.withAlpha(0.10), mc.mix(render::kBlack, 0.2).withAlpha(0.55), 0.8);
  std::vector<std::vector<Vec2>> footprints;
  for (const auto& st : m.strategy.stops)
    footprints.push_back(project(footprint(m.strategy, st), view));
  p.polygons(footprints, fp);
}

/// The surface layer, far to near: each surface's points, its boundary and its mission's
/// footprints.
void drawSurfaceLayer(render::Panel& p, const OverviewContent& c, const View& view) {
  for (const Surface* s : surfacesFarToNear(c.scene, view)) {
    const Color pale = surfaceColor(s->id).mix(render::kWhite, 0.45);
    p.markers(project(s->inliers, view, c.stride),
              render::Style{pale, pale, 0.0, false, render::Marker::Square, 1.8});
    p.polygon(project(s->boundary, view),
              render::lineStyle(surfaceColor(s->id).mix(render::kBlack, 0.3), 2.4));
    if (const auto* m = missionOf(c.missions, s->id)) drawFootprints(p, *m, view);
  }
}

/// The mission layer, far to near: each path, its feasible stops (surface colour) and
/// infeasible ones (red crosses), the surface points no photo images, and (without an
/// ordered flight) the start. stop_px: stop marker size [px].
void drawMissionLayer(render::Panel& p, const OverviewContent& c, const View& view,
                      double stop_px) {
  const render::Style bad_here{render::kRed, render::kRed,          stop_px > 4.0 ? 2.0 : 1.2,
                               false,        render::Marker::Cross, stop_px * 1.4};
  for (const auto* mp : missionsFarToNear(c.missions, view)) {
    const auto& m = *mp;
    const Color col = surfaceColor(m.surface_id);
    if (m.waypoints.size() >= 2)
      p.polyline(project(m.waypoints, view), render::lineStyle(col.mix(kPathDark, 0.5), 1.6));
    PointList good, bad;
    for (std::size_t i = 0; i < m.strategy.stops.size(); ++i) {
      const bool problem =
          i < m.stop_problems.size() && m.stop_problems[i] != planning::StopProblem::None;
      (problem ? bad : good).push_back(m.strategy.stops[i].position);
    }
    render::Style good_style = render::markerStyle(col, render::Marker::Circle, stop_px);
    if (stop_px < 4.0) good_style.line_width_px = 0.0;
    p.markers(project(good, view), good_style);
    p.markers(project(bad, view), bad_here);
    p.markers(project(m.coverage.uncovered_points, view), kUncoveredStyle);
    if (c.flight == nullptr && !m.waypoints.empty())
      p.markers(project({m.waypoints.front()}, view), startStyle());
  }
}

/// One view's panel at rect [px]: the cloud, surface and mission layers, then the flight.
void drawView(render::Figure& fig, const std::array<double, 4>& rect, const View& view,
              const OverviewContent& c) {
  render::PanelOptions po;
  po.title = view.title;
  po.x.label = view.x_label;
  po.y.label = view.y_label;
  po.equal_aspect = true;
  po.legend = render::Corner::None;
  po.scale_bar = render::Corner::BottomRight;
  render::Panel& p = fig.addPanel(rect[0], rect[1], rect[2], rect[3], po);
  drawCloudLayer(p, c, view);
  drawSurfaceLayer(p, c, view);
  drawMissionLayer(p, c, view, stopMarkerPx(c, view, rect));
  if (c.flight != nullptr) drawFlight(p, *c.flight, view);
}

/// The legend of the symbols; the footprint size and standoff are the first planned
/// mission's (0 without one).
std::vector<LegendEntry> symbolEntries(const OverviewContent& c) {
  double footprint_w = 0.0, footprint_h = 0.0, standoff = 0.0;
  for (const auto& m : c.missions) {
    if (m.strategy.stops.empty()) continue;
    footprint_w = m.strategy.camera.footprint_w_m;
    footprint_h = m.strategy.camera.footprint_h_m;
    standoff = m.strategy.camera.standoff_m;
    break;
  }
  const render::Style bad_style{render::kRed, render::kRed, 2.0, false, render::Marker::Cross, 9.0};
  const Color demo = render::palette(0);
  return {
      {"surface points (colour = surface)",
       render::markerStyle(demo.mix(render::kWhite, 0.45), render::Marker::Square, 7.0),
       LegendKind::Marker},
      {"surface boundary", render::lineStyle(demo.mix(render::kBlack, 0.3), 2.4), LegendKind::Line},
      {"obstacle points", render::markerStyle(kObstacleColor, render::Marker::Square, 7.0),
       LegendKind::Marker},
      {"other cloud points", render::markerStyle(kCloudColor, render::Marker::Square, 7.0),
       LegendKind::Marker},
      {"photo footprint " + formatFixed(footprint_w, 2) + " × " + formatFixed(footprint_h, 2) +
           " m",
       render::patchStyle(demo.withAlpha(0.15), demo.mix(render::kBlack, 0.2)), LegendKind::Patch},
      {"photo stop (UAV, " + formatFixed(standoff, 2) + " m off)",
       render::markerStyle(demo, render::Marker::Circle, 7.0), LegendKind::Marker},
      {"flight path (waypoints)", render::lineStyle(demo.mix(kPathDark, 0.5), 1.8),
       LegendKind::Line},
      c.flight != nullptr
          ? LegendEntry{"sortie k (colour), home to home", render::lineStyle(sortieColor(0), 1.4),
                        LegendKind::Line}
          : LegendEntry{"start of a surface's flight", startStyle(), LegendKind::Marker},
      {"infeasible stop (not flown)", bad_style, LegendKind::Marker},
      {"surface point no photo images", kUncoveredStyle, LegendKind::Marker},
  };
}

/// One legend row per surface (id, facing, area, mission status, stops, path length);
/// when they do not fit in max_rows, the last row says how many more there are.
std::vector<LegendEntry> surfaceRows(const OverviewContent& c, std::size_t max_rows) {
  std::vector<LegendEntry> rows;
  for (const auto& s : c.scene.surfaces) {
    if (rows.size() + 1 >= max_rows && rows.size() + 1 < c.scene.surfaces.size()) {
      rows.push_back({"... " + std::to_string(c.scene.surfaces.size() - rows.size()) + " more",
                      render::Style{}, LegendKind::Line});
      break;
    }
    std::ostringstream os;
    os << s.id << ": " << facing(s.plane.normal) << ", " << formatFixed(s.area_m2, 1) << " m²";
    if (const auto* m = missionOf(c.missions, s.id)) {
      os << ", " << planning::toString(m->status) << ", " << m->strategy.stops.size() << " stops";
      if (planning::flyable(m->status)) os << ", " << formatFixed(m->path_length_m, 1) << " m";
    } else {
      os << ", not planned";
    }
    const Color col = surfaceColor(s.id);
    rows.push_back({os.str(),
                    render::patchStyle(col.mix(render::kWhite, 0.3), col.mix(render::kBlack, 0.3)),
                    LegendKind::Patch});
  }
  if (rows.empty()) rows.push_back({"no surface detected", render::Style{}, LegendKind::Line});
  return rows;
}

/// The "How to read" lines (heading first), for an ordered flight or per-surface flights.
std::vector<std::string> howToRead(bool flown) {
  if (flown) {
    return {
        "How to read",
        "One flight from home: the surfaces in the order",
        "of the numbers, each row by row at the standoff,",
        "split into battery sorties (one colour each);",
        "each stop takes one photo (footprint rectangle).",
        "Views are orthographic, nearer objects on top;",
        "the scale bar gives the size. Numbers: local",
        "frame in metres, x east, y north, z up.",
    };
  }
  return {
      "How to read",
      "Each surface is flown on its own: from its",
      "start (triangle) the UAV visits the photo stops",
      "row by row at the standoff, camera on the surface;",
      "each stop takes one photo (footprint rectangle).",
      "Views are orthographic, nearer objects on top;",
      "the scale bar gives the size. Numbers: local",
      "frame in metres, x east, y north, z up.",
  };
}

/// The legend column right of the views: symbols, one row per surface, then how to
/// read the picture (lines that would pass the bottom edge are left out).
void drawLegendColumn(render::Figure& fig, const OverviewLayout& l, const OverviewContent& c) {
  const double lx = l.width - l.legend_w - l.gap + 4.0;
  std::vector<LegendEntry> symbols = symbolEntries(c);
  if (c.flight != nullptr) {
    symbols.push_back({"home (take-off, landing)", kHomeStyle, LegendKind::Marker});
    symbols.push_back({"n: n-th surface of the flight", render::Style{}, LegendKind::Line});
  }
  fig.text(lx, l.top + 14.0, "Legend", {15.0, render::kBlack, render::Align::Left, true});
  fig.legend(lx, l.top + 24.0, symbols, 12.0);

  const double sy = l.top + 24.0 + 12.0 * 1.55 * static_cast<double>(symbols.size()) + 12.0 + 36.0;
  fig.text(lx, sy, "Surfaces", {15.0, render::kBlack, render::Align::Left, true});
  const std::size_t max_rows =
      static_cast<std::size_t>(std::max(1.0, (l.height - sy - 40.0) / (12.0 * 1.55)));
  const std::vector<LegendEntry> rows = surfaceRows(c, max_rows);
  fig.legend(lx, sy + 10.0, rows, 12.0);

  const double hy = sy + 10.0 + 12.0 * 1.55 * static_cast<double>(rows.size()) + 12.0 + 40.0;
  const std::vector<std::string> help = howToRead(c.flight != nullptr);
  for (std::size_t i = 0; i < help.size() && hy + 18.0 * static_cast<double>(i) < l.height - 10.0;
       ++i) {
    fig.text(lx, hy + 18.0 * static_cast<double>(i), help[i],
             {i == 0 ? 15.0 : 12.5, i == 0 ? render::kBlack : Color::rgb(50, 50, 50),
              render::Align::Left, i == 0});
  }
}

}  // namespace

render::Figure overviewFigure(const Scene& scene,
                              const std::vector<planning::SurfaceMission>& missions,
                              const OverviewOptions& options, const planning::FlightPlan* flight) {
  render::Figure fig(options.width_px, options.height_px);
  const OverviewLayout layout = overviewLayout(options);
  const OverviewContent content = overviewContent(scene, missions, options, flight);
  drawHeader(fig, options.title, content);
  for (std::size_t vi = 0; vi < kViews.size(); ++vi)
    drawView(fig, layout.views[vi], kViews[vi], content);
  drawLegendColumn(fig, layout, content);
  return fig;
}

ViewFiles renderViews(const Scene& scene, const std::vector<planning::SurfaceMission>& missions,
                      const OverviewOptions& options, const planning::FlightPlan* flight,
                      const planning::FleetPlan* fleet) {
  // The PLY text and the overview are independent: the PLY on a second thread
  // (here, if no thread can be started).
  std::future<std::string> ply;
  try {
    ply = std::async(std::launch::async, [&] { return sceneToPly(scene, missions); });
  } catch (const std::system_error&) {
    ply = std::async(std::launch::deferred, [&] { return sceneToPly(scene, missions); });
  }
  // The 3D page (view/mission_page.h) on a third; detect's scene alone has no mission.
  std::future<std::string> html;
  auto page = [&] {
    MissionPageOptions page_options;
    // "name: uavip mission overview" -> "name: uavip mission", as `uavip view` names it.
    const std::string suffix = " overview";
    page_options.title = options.title;
    if (page_options.title.size() > suffix.size() &&
        page_options.title.compare(page_options.title.size() - suffix.size(), suffix.size(),
                                   suffix) == 0)
      page_options.title.resize(page_options.title.size() - suffix.size());
    page_options.clearance_m = options.clearance_m;
    page_options.geo = options.geo;
    const bool scene_only = missions.empty() && flight == nullptr;
    return scene_only ? missionPage(scene, nullptr, page_options)
                      : missionPage(scene, missions, flight, page_options, fleet);
  };
  try {
    html = std::async(std::launch::async, page);
  } catch (const std::system_error&) {
    html = std::async(std::launch::deferred, page);
  }
  std::string png = overviewFigure(scene, missions, options, flight).png();
  return {ply.get(), pathsToObj(missions, flight), std::move(png), html.get()};
}

void stageViews(io::StagedOutputs& outputs, const std::string& out_dir, const ViewFiles& views) {
  namespace fs = std::filesystem;
  outputs.write((fs::path(out_dir) / "scene.ply").string(), views.ply);
  outputs.write((fs::path(out_dir) / "path.obj").string(), views.obj);
  outputs.write((fs::path(out_dir) / "overview.png").string(), views.png);
  outputs.write((fs::path(out_dir) / "mission.html").string(), views.html);
}

void writeViews(io::StagedOutputs& outputs, const std::string& out_dir, const Scene& scene,
                const std::vector<planning::SurfaceMission>& missions,
                const OverviewOptions& options, const planning::FlightPlan* flight) {
  stageViews(outputs, out_dir, renderViews(scene, missions, options, flight));
}

}  // namespace uavip::view
