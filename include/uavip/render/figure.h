#pragma once
/// \file
/// A small 2D drawing module on Cairo, shared by the mission overview picture
/// (view/views.h) and the benchmark plots. It knows nothing of missions or scenes.
///
/// Model (retained mode): a Figure is a canvas of width × height pixels holding
/// Panels and free text. A Panel is a rectangle of the canvas with a data frame
/// (x right, y up): add polylines, polygons, markers and text in DATA coordinates;
/// the data ranges come from everything added (5 % margin) unless fixed in the
/// Axis, and the picture is only drawn when the figure is encoded (png(), svg(),
/// writePng(), writeSvg()). A panel can draw axes with ticks and labels, a grid, a
/// title, a legend (from the labels given to primitives plus explicit entries), a
/// scale bar, and keep 1 data unit = 1 data unit on both axes (maps).
///
/// Log axes (Scale::Log10) drop primitives' points whose coordinate on that axis is
/// <= 0 (a polyline is split there); ticks are at powers of ten.
///
/// Sizes (line widths, marker sizes, fonts) are in pixels of the canvas. Output is
/// deterministic for the same calls. Not thread-safe; distinct figures may be used
/// from distinct threads.
///
/// Minimal use:
/// \code
///   render::Figure fig(800, 500);
///   render::PanelOptions o;
///   o.title = "time vs path length";
///   o.x = {"path length [m]"};
///   o.y = {"time [s]", render::Scale::Log10};
///   auto& p = fig.addPanel(0, 0, 800, 500, o);
///   p.markers({{10, 0.02}, {12, 0.5}}, render::markerStyle(render::palette(0)), "A*");
///   fig.writePng("plot.png");
/// \endcode
/// See render/plot.h for scatter/line plots in one call.

#include <Eigen/Core>
#include <deque>
#include <optional>
#include <string>
#include <vector>

namespace uavip::render {

/// A point in data (or pixel) coordinates.
using Vec2 = Eigen::Vector2d;

/// An RGBA colour, components in [0, 1].
struct Color {
  double r{0.0}, g{0.0}, b{0.0}, a{1.0};
  /// From 0–255 components.
  static Color rgb(int r, int g, int b, double a = 1.0);
  /// The same colour with alpha `a`.
  Color withAlpha(double alpha) const { return {r, g, b, alpha}; }
  /// Linear blend toward `other`: t = 0 gives *this, t = 1 gives other (alpha too).
  Color mix(const Color& other, double t) const;
  /// 0–255 red, green, blue (alpha ignored), rounded.
  int red8() const;
  int green8() const;
  int blue8() const;
};

/// Named colours.
inline const Color kBlack{0.0, 0.0, 0.0};
inline const Color kWhite{1.0, 1.0, 1.0};
inline const Color kGrey{0.6, 0.6, 0.6};
inline const Color kRed{0.84, 0.15, 0.16};

/// Colour i (any int, cycling) of a 10-colour categorical palette (Tableau 10),
/// distinguishable for the common forms of colour blindness.
Color palette(int i);

/// Marker shapes.
enum class Marker { Circle, Square, Triangle, Diamond, Cross, Plus };

/// How a primitive is drawn. Sizes in pixels.
struct Style {
  Color stroke{kBlack};       ///< line / outline colour
  std::optional<Color> fill;  ///< fill of polygons and markers (none: outline only)
  double line_width_px{1.5};  ///< 0: no outline
  bool dashed{false};
  Marker marker{Marker::Circle};
  double marker_size_px{6.0};  ///< marker width [px]
};

/// A line style: colour and width.
Style lineStyle(const Color& color, double width_px = 1.5, bool dashed = false);
/// Filled markers of one colour (thin darker outline).
Style markerStyle(const Color& color, Marker marker = Marker::Circle, double size_px = 6.0);
/// A filled polygon with an outline.
Style patchStyle(const Color& fill, const Color& stroke, double width_px = 1.0);

/// Axis scale.
enum class Scale { Linear, Log10 };

/// One axis of a panel.
struct Axis {
  std::string label;  ///< drawn along the axis, e.g. "x east [m]"
  Scale scale{Scale::Linear};
  std::optional<double> min;  ///< fixed lower end (else from the data)
  std::optional<double> max;  ///< fixed upper end (else from the data)
};

/// Where a legend or scale bar goes inside the plot area (None: not drawn).
enum class Corner { None, TopLeft, TopRight, BottomLeft, BottomRight };

/// Horizontal anchor of text.
enum class Align { Left, Center, Right };

/// How text is drawn.
struct TextStyle {
  double size_px{13.0};
  Color color{kBlack};
  Align align{Align::Left};
  bool bold{false};
  bool vertical{false};  ///< rotated 90° counter-clockwise (reads bottom to top)
};

/// Options of a panel.
struct PanelOptions {
  std::string title;  ///< above the plot area
  Axis x;
  Axis y;
  bool axes{true};                  ///< frame, ticks and tick labels
  bool grid{true};                  ///< light grid lines at the ticks
  bool equal_aspect{false};         ///< one x unit as long as one y unit (linear axes only)
  Corner legend{Corner::TopRight};  ///< drawn only when there are entries
  Corner scale_bar{Corner::None};   ///< a bar of a round length in x units
  std::string scale_bar_unit{"m"};  ///< text after the bar's length
  Color background{kWhite};         ///< fill of the plot area
};

/// What a legend entry shows next to its label.
enum class LegendKind { Line, Marker, Patch };

/// One legend line.
struct LegendEntry {
  std::string label;
  Style style;
  LegendKind kind{LegendKind::Line};
};

/// Where a panel puts its data: the plot area in pixels and the data range shown.
/// Pixel y grows downward; data y grows upward.
struct Frame {
  double left_px{0.0}, top_px{0.0}, width_px{0.0}, height_px{0.0};  ///< plot area
  double x_min{0.0}, x_max{1.0}, y_min{0.0}, y_max{1.0};            ///< data range (not log)
  Scale x_scale{Scale::Linear}, y_scale{Scale::Linear};

  /// Data → pixel coordinates (log axes map log10 of the value).
  Vec2 toPixel(const Vec2& data) const;
};

/// "Nice" tick values within [lo, hi]: multiples of 1, 2 or 5 × 10^k with about
/// `target` ticks for Linear; powers of ten (and 2, 5 × 10^k when the range is
/// under two decades) for Log10. Empty if lo >= hi or (Log10) lo <= 0.
std::vector<double> ticks(double lo, double hi, Scale scale, int target = 6);

/// Short text of a tick value: "0.25", "1e-04", "1000".
std::string tickLabel(double value);

/// A rectangle of the figure with a data frame. Created by Figure::addPanel; lives
/// as long as its figure (the reference stays valid when more panels are added).
class Panel {
 public:
  /// Open polyline through `points` (data coordinates). `label` adds a legend entry.
  void polyline(const std::vector<Vec2>& points, const Style& style, const std::string& label = {});
  /// Closed polygon, filled if style.fill is set.
  void polygon(const std::vector<Vec2>& points, const Style& style, const std::string& label = {});
  /// Many closed polygons of one style drawn as one path: one fill and one stroke
  /// (their union is filled once, so overlaps do not darken). Thousands of photo
  /// footprints cost one Cairo stroke instead of thousands.
  void polygons(const std::vector<std::vector<Vec2>>& polygons, const Style& style,
                const std::string& label = {});
  /// One marker at each point.
  void markers(const std::vector<Vec2>& points, const Style& style, const std::string& label = {});
  /// Text anchored at a data point (baseline at the point's y).
  void text(const Vec2& at, const std::string& text, const TextStyle& style = {});
  /// An explicit legend entry (after those from labels, in order of calls).
  void legendEntry(const LegendEntry& entry);

  const PanelOptions& options() const { return options_; }
  /// The frame as it will be drawn with what was added so far.
  Frame frame() const;

 private:
  friend class Figure;
  enum class Kind {
    Polyline,
    Polygon,
    Polygons,
    Markers,
    Text
  };  ///< Polygons: NaN-separated rings
  struct Item {
    Kind kind{Kind::Polyline};
    std::vector<Vec2> points;
    Style style;
    std::string text;
    TextStyle text_style;
  };
  Panel(double x_px, double y_px, double w_px, double h_px, PanelOptions options);
  void draw(void* cairo) const;  // cairo_t*, kept out of this header

  double x_px_, y_px_, w_px_, h_px_;
  PanelOptions options_;
  std::vector<Item> items_;
  std::vector<LegendEntry> legend_;
};

/// A canvas of panels and free text, encoded as PNG or SVG.
class Figure {
 public:
  /// Throws uavip::InputError unless 1 <= width, height <= 16384 px.
  Figure(int width_px, int height_px, const Color& background = kWhite);

  int width() const { return width_px_; }
  int height() const { return height_px_; }

  /// A panel occupying the given pixel rectangle (including room for its title,
  /// tick labels and axis labels).
  Panel& addPanel(double x_px, double y_px, double w_px, double h_px, const PanelOptions& options);
  /// Text at a pixel position (baseline at y).
  void text(double x_px, double y_px, const std::string& text, const TextStyle& style = {});
  /// A filled rectangle in pixels (backgrounds, swatches).
  void rectangle(double x_px, double y_px, double w_px, double h_px, const Style& style);
  /// A legend box with its top-left corner at a pixel position.
  void legend(double x_px, double y_px, const std::vector<LegendEntry>& entries,
              double size_px = 13.0);

  /// The picture as PNG file bytes (8-bit RGB(A)).
  std::string png() const;
  /// The picture as SVG text.
  std::string svg() const;
  /// Writes png() / svg() to a file (not atomically: the io module does that).
  /// Throws std::runtime_error naming the path.
  void writePng(const std::string& path) const;
  void writeSvg(const std::string& path) const;

 private:
  enum class Kind { Text, Rectangle, Legend };
  struct Item {
    Kind kind{Kind::Text};
    double x{0.0}, y{0.0}, w{0.0}, h{0.0};
    std::string text;
    TextStyle text_style;
    Style style;
    std::vector<LegendEntry> entries;
  };
  void draw(void* cairo) const;

  int width_px_;
  int height_px_;
  Color background_;
  std::deque<Panel> panels_;
  std::vector<Item> items_;
};

/// A decoded raster image (for tests and checks of written pictures).
struct Raster {
  int width{0};
  int height{0};
  std::vector<unsigned int> argb;  ///< premultiplied 0xAARRGGBB, row-major, top row first
  /// Colour at a pixel (alpha un-premultiplied). Throws std::out_of_range off the image.
  Color at(int x, int y) const;
};

/// Decodes PNG bytes. Throws std::runtime_error if they are not a PNG.
Raster decodePng(const std::string& bytes);

}  // namespace uavip::render
