#pragma once
/// \file
/// Scatter and line plots in one call, on render/figure.h: one panel with axes,
/// grid, title and legend. For benchmark results (e.g. time vs path length per
/// planner, log time axis):
/// \code
///   std::vector<render::Series> s(2);
///   s[0].label = "astar";    s[0].x = {31.7, 30.2}; s[0].y = {0.05, 0.04};
///   s[1].label = "ompl_rrt"; s[1].x = {35.0, 33.1}; s[1].y = {1.2, 0.9};
///   render::PlotOptions o;
///   o.title = "planning time vs path length";
///   o.x.label = "path length [m]";
///   o.y = {"time [s]", render::Scale::Log10};
///   io::writeFileAtomic("bench.png", render::plot(s, o).png());   // or .svg()
/// \endcode
/// Series get palette colours and distinct markers in order unless given. On a log
/// axis, points with a value <= 0 on that axis are left out (see figure.h).

#include <optional>
#include <string>
#include <vector>

#include "uavip/render/figure.h"

namespace uavip::render {

/// One data series; x and y must have the same length.
struct Series {
  std::string label;  ///< legend text (empty: not in the legend)
  std::vector<double> x;
  std::vector<double> y;
  bool markers{true};            ///< a marker at each point (scatter)
  bool lines{false};             ///< join the points in the given order (line plot)
  std::optional<Color> color;    ///< default: palette(series index)
  std::optional<Marker> marker;  ///< default: cycles Circle, Square, Triangle, Diamond, Cross, Plus
  double marker_size_px{7.0};
  double line_width_px{1.8};
};

/// Options of a plot.
struct PlotOptions {
  std::string title;
  Axis x;
  Axis y;
  int width_px{900};
  int height_px{560};
  Corner legend{Corner::TopLeft};
  bool grid{true};
};

/// Builds the plot. Throws uavip::InputError if a series has x.size() != y.size()
/// (naming the series) or a size is out of range.
Figure plot(const std::vector<Series>& series, const PlotOptions& options);

}  // namespace uavip::render
