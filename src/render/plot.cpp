#include "uavip/render/plot.h"

#include <array>

#include "uavip/core/error.h"

namespace uavip::render {

Figure plot(const std::vector<Series>& series, const PlotOptions& options) {
  Figure fig(options.width_px, options.height_px);
  PanelOptions p;
  p.title = options.title;
  p.x = options.x;
  p.y = options.y;
  p.grid = options.grid;
  p.legend = options.legend;
  Panel& panel = fig.addPanel(0.0, 0.0, options.width_px, options.height_px, p);
  static const std::array<Marker, 6> kMarkers{Marker::Circle,  Marker::Square, Marker::Triangle,
                                              Marker::Diamond, Marker::Cross,  Marker::Plus};
  for (std::size_t i = 0; i < series.size(); ++i) {
    const Series& s = series[i];
    require(s.x.size() == s.y.size(), "plot: series '" + s.label + "'",
            "x and y must have the same length, got " + std::to_string(s.x.size()) + " and " +
                std::to_string(s.y.size()));
    std::vector<Vec2> pts;
    pts.reserve(s.x.size());
    for (std::size_t k = 0; k < s.x.size(); ++k) pts.emplace_back(s.x[k], s.y[k]);
    const Color color = s.color ? *s.color : palette(static_cast<int>(i));
    const Marker marker = s.marker ? *s.marker : kMarkers[i % kMarkers.size()];
    Style line = lineStyle(color, s.line_width_px);
    Style mark = markerStyle(color, marker, s.marker_size_px);
    if (s.lines) panel.polyline(pts, line);
    if (s.markers) panel.markers(pts, mark);
    if (!s.label.empty()) {
      if (s.markers) {
        panel.legendEntry({s.label, mark, LegendKind::Marker});
      } else if (s.lines) {
        panel.legendEntry({s.label, line, LegendKind::Line});
      }
    }
  }
  return fig;
}

}  // namespace uavip::render
