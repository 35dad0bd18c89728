#include "uavip/render/figure.h"

#include <cairo-svg.h>
#include <cairo.h>
#include <fontconfig/fontconfig.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <unordered_set>
#include <utility>

#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/voxel_key.h"

namespace uavip::render {
namespace {

constexpr const char* kFont = "DejaVu Sans";

using SurfacePtr = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using ContextPtr = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

cairo_t* ctx(void* p) { return static_cast<cairo_t*>(p); }

/// Cairo and fontconfig keep font caches for the life of the process;
/// release them at exit so leak checkers (ASan/LSan, valgrind) see a clean exit.
/// At exit no cairo object of ours is alive (all are scoped).
void releaseCairoAtExit() {
  static std::once_flag once;
  std::call_once(once, [] {
    std::atexit([] {
      cairo_debug_reset_static_data();
      FcFini();
    });
  });
}

void setColor(cairo_t* cr, const Color& c) { cairo_set_source_rgba(cr, c.r, c.g, c.b, c.a); }

void applyLine(cairo_t* cr, const Style& s) {
  setColor(cr, s.stroke);
  cairo_set_line_width(cr, s.line_width_px);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  if (s.dashed) {
    const std::array<double, 2> dash{6.0, 4.0};
    cairo_set_dash(cr, dash.data(), 2, 0.0);
  } else {
    cairo_set_dash(cr, nullptr, 0, 0.0);
  }
}

/// Width and height of text as drawn by drawText.
Vec2 textSize(cairo_t* cr, const std::string& text, const TextStyle& style) {
  cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL,
                         style.bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, style.size_px);
  cairo_text_extents_t ext;
  cairo_text_extents(cr, text.c_str(), &ext);
  return {ext.x_advance, style.size_px};
}

void drawText(cairo_t* cr, double x, double y, const std::string& text, const TextStyle& style) {
  if (text.empty()) return;
  const double w = textSize(cr, text, style).x();
  const double shift = style.align == Align::Left     ? 0.0
                       : style.align == Align::Center ? -w / 2.0
                                                      : -w;
  cairo_save(cr);
  cairo_translate(cr, x, y);
  if (style.vertical) cairo_rotate(cr, -kPi / 2.0);
  setColor(cr, style.color);
  cairo_move_to(cr, shift, 0.0);
  cairo_show_text(cr, text.c_str());
  cairo_restore(cr);
}

/// Adds one marker's outline to the current path.
void markerPath(cairo_t* cr, Marker m, double x, double y, double size) {
  const double h = size / 2.0;
  switch (m) {
    case Marker::Circle:
      cairo_new_sub_path(cr);
      cairo_arc(cr, x, y, h, 0.0, 2.0 * kPi);
      break;
    case Marker::Square:
      cairo_rectangle(cr, x - h, y - h, size, size);
      break;
    case Marker::Triangle:
      cairo_move_to(cr, x, y - h * 1.15);
      cairo_line_to(cr, x + h * 1.05, y + h * 0.7);
      cairo_line_to(cr, x - h * 1.05, y + h * 0.7);
      cairo_close_path(cr);
      break;
    case Marker::Diamond:
      cairo_move_to(cr, x, y - h * 1.2);
      cairo_line_to(cr, x + h, y);
      cairo_line_to(cr, x, y + h * 1.2);
      cairo_line_to(cr, x - h, y);
      cairo_close_path(cr);
      break;
    case Marker::Cross:
      cairo_move_to(cr, x - h, y - h);
      cairo_line_to(cr, x + h, y + h);
      cairo_move_to(cr, x - h, y + h);
      cairo_line_to(cr, x + h, y - h);
      break;
    case Marker::Plus:
      cairo_move_to(cr, x - h, y);
      cairo_line_to(cr, x + h, y);
      cairo_move_to(cr, x, y - h);
      cairo_line_to(cr, x, y + h);
      break;
  }
}

/// Exact key of a cell of a 2D lattice (whole-number coordinates within ±1e9, which
/// callers ensure by clamping or skipping).
std::uint64_t cellKey(double x, double y) {
  return planeCellKey(static_cast<std::int64_t>(x), static_cast<std::int64_t>(y), "figure");
}

/// Hash of a pair of cell keys (a segment between two cells).
struct CellPairHash {
  std::size_t operator()(const std::pair<std::uint64_t, std::uint64_t>& p) const {
    return std::hash<std::uint64_t>()(p.first) ^
           (std::hash<std::uint64_t>()(p.second) * 0x9E3779B97F4A7C15ULL);
  }
};

bool strokeOnly(Marker m) { return m == Marker::Cross || m == Marker::Plus; }

/// Fills and strokes the current path of markers with a style.
void finishMarkers(cairo_t* cr, const Style& s) {
  if (strokeOnly(s.marker)) {
    Style line = s;
    if (s.fill) line.stroke = *s.fill;
    line.line_width_px = std::max(s.line_width_px, 1.5);
    line.dashed = false;
    applyLine(cr, line);
    cairo_stroke(cr);
    return;
  }
  if (s.fill) {
    setColor(cr, *s.fill);
    if (s.line_width_px > 0.0) {
      cairo_fill_preserve(cr);
    } else {
      cairo_fill(cr);
      return;
    }
  }
  if (s.line_width_px > 0.0) {
    Style line = s;
    line.dashed = false;
    applyLine(cr, line);
    cairo_stroke(cr);
  } else {
    cairo_new_path(cr);
  }
}

void legendSwatch(cairo_t* cr, const LegendEntry& e, double x, double y, double w, double h) {
  const double cy = y + h / 2.0;
  switch (e.kind) {
    case LegendKind::Line:
      applyLine(cr, e.style);
      cairo_move_to(cr, x, cy);
      cairo_line_to(cr, x + w, cy);
      cairo_stroke(cr);
      break;
    case LegendKind::Marker:
      markerPath(cr, e.style.marker, x + w / 2.0, cy, std::min(e.style.marker_size_px, h) + 1.0);
      finishMarkers(cr, e.style);
      break;
    case LegendKind::Patch:
      cairo_rectangle(cr, x + 2.0, y + 2.0, w - 4.0, h - 4.0);
      finishMarkers(cr, Style{e.style.stroke, e.style.fill, std::max(e.style.line_width_px, 1.0),
                              e.style.dashed, Marker::Square, 0.0});
      break;
  }
}

/// Size of a legend box for these entries.
Vec2 legendSize(cairo_t* cr, const std::vector<LegendEntry>& entries, double size_px) {
  double w = 0.0;
  for (const auto& e : entries) w = std::max(w, textSize(cr, e.label, TextStyle{size_px}).x());
  const double row = size_px * 1.55;
  return {w + 30.0 + 8.0 + 16.0, row * static_cast<double>(entries.size()) + 12.0};
}

void drawLegend(cairo_t* cr, double x, double y, const std::vector<LegendEntry>& entries,
                double size_px) {
  if (entries.empty()) return;
  const Vec2 size = legendSize(cr, entries, size_px);
  cairo_rectangle(cr, x, y, size.x(), size.y());
  setColor(cr, kWhite.withAlpha(0.88));
  cairo_fill_preserve(cr);
  applyLine(cr, lineStyle(kGrey, 1.0));
  cairo_stroke(cr);
  const double row = size_px * 1.55;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const double ry = y + 6.0 + row * static_cast<double>(i);
    legendSwatch(cr, entries[i], x + 8.0, ry + row * 0.12, 30.0, row * 0.76);
    drawText(cr, x + 8.0 + 30.0 + 8.0, ry + row * 0.5 + size_px * 0.36, entries[i].label,
             TextStyle{size_px});
  }
}

double roundDown125(double v) {
  const double mag = std::pow(10.0, std::floor(std::log10(v)));
  const double n = v / mag;
  return (n >= 5.0 ? 5.0 : n >= 2.0 ? 2.0 : 1.0) * mag;
}

bool usable(double v, Scale s) { return std::isfinite(v) && (s == Scale::Linear || v > 0.0); }

/// Range of data along one axis, with margins; the axis' fixed ends win.
void axisRange(double lo, double hi, bool any, const Axis& axis, double& out_lo, double& out_hi) {
  const bool log = axis.scale == Scale::Log10;
  double a = 0.0, b = 1.0;  // in (log) axis space
  if (any) {
    a = log ? std::log10(lo) : lo;
    b = log ? std::log10(hi) : hi;
    const double span = b - a;
    const double pad = span > 0.0 ? 0.05 * span : 0.5;
    a -= pad;
    b += pad;
  } else if (log) {
    a = 0.0;
    b = 1.0;
  }
  out_lo = log ? std::pow(10.0, a) : a;
  out_hi = log ? std::pow(10.0, b) : b;
  if (axis.min && usable(*axis.min, axis.scale)) out_lo = *axis.min;
  if (axis.max && usable(*axis.max, axis.scale)) out_hi = *axis.max;
  if (!(out_hi > out_lo)) {  // degenerate fixed range
    if (log) {
      out_hi = out_lo * 10.0;
    } else {
      out_hi = out_lo + 1.0;
    }
  }
}

cairo_status_t appendToString(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

struct ReadCursor {
  const std::string* bytes;
  std::size_t pos;
};

cairo_status_t readFromString(void* closure, unsigned char* data, unsigned int length) {
  auto* c = static_cast<ReadCursor*>(closure);
  if (c->pos + length > c->bytes->size()) return CAIRO_STATUS_READ_ERROR;
  std::memcpy(data, c->bytes->data() + c->pos, length);
  c->pos += length;
  return CAIRO_STATUS_SUCCESS;
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error(path + ": cannot write");
}

}  // namespace

// ---------------------------------------------------------------- colours, styles

Color Color::rgb(int r, int g, int b, double a) { return {r / 255.0, g / 255.0, b / 255.0, a}; }

Color Color::mix(const Color& o, double t) const {
  return {r + (o.r - r) * t, g + (o.g - g) * t, b + (o.b - b) * t, a + (o.a - a) * t};
}

int Color::red8() const { return static_cast<int>(std::lround(std::clamp(r, 0.0, 1.0) * 255.0)); }
int Color::green8() const { return static_cast<int>(std::lround(std::clamp(g, 0.0, 1.0) * 255.0)); }
int Color::blue8() const { return static_cast<int>(std::lround(std::clamp(b, 0.0, 1.0) * 255.0)); }

Color palette(int i) {
  static const std::array<Color, 10> kTab10{Color::rgb(31, 119, 180), Color::rgb(255, 127, 14),
                                            Color::rgb(44, 160, 44),  Color::rgb(148, 103, 189),
                                            Color::rgb(23, 190, 207), Color::rgb(227, 119, 194),
                                            Color::rgb(188, 189, 34), Color::rgb(140, 86, 75),
                                            Color::rgb(214, 39, 40),  Color::rgb(127, 127, 127)};
  const int n = static_cast<int>(kTab10.size());
  return kTab10[static_cast<std::size_t>(((i % n) + n) % n)];
}

Style lineStyle(const Color& color, double width_px, bool dashed) {
  Style s;
  s.stroke = color;
  s.line_width_px = width_px;
  s.dashed = dashed;
  return s;
}

Style markerStyle(const Color& color, Marker marker, double size_px) {
  Style s;
  s.stroke = color.mix(kBlack, 0.35);
  s.fill = color;
  s.line_width_px = 0.8;
  s.marker = marker;
  s.marker_size_px = size_px;
  return s;
}

Style patchStyle(const Color& fill, const Color& stroke, double width_px) {
  Style s;
  s.stroke = stroke;
  s.fill = fill;
  s.line_width_px = width_px;
  return s;
}

// ---------------------------------------------------------------- ticks

std::vector<double> ticks(double lo, double hi, Scale scale, int target) {
  std::vector<double> out;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return out;
  target = std::max(target, 2);
  if (scale == Scale::Log10) {
    if (lo <= 0.0) return out;
    const int k0 = static_cast<int>(std::ceil(std::log10(lo) - 1e-9));
    const int k1 = static_cast<int>(std::floor(std::log10(hi) + 1e-9));
    const bool dense = hi / lo < 100.0;
    for (int k = k0 - 1; k <= k1; ++k) {
      const double p = std::pow(10.0, k);
      for (double m : {1.0, 2.0, 5.0}) {
        if (m != 1.0 && !dense) continue;
        const double v = m * p;
        if (v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9)) out.push_back(v);
      }
    }
    if (out.size() < 2) {
      out.clear();
      for (double v : ticks(lo, hi, Scale::Linear, target))
        if (v > 0.0) out.push_back(v);
    }
    return out;
  }
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double n = raw / mag;
  const double step = (n < 1.5 ? 1.0 : n < 3.0 ? 2.0 : n < 7.0 ? 5.0 : 10.0) * mag;
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9; v += step) {
    out.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
  }
  return out;
}

std::string tickLabel(double value) {
  std::array<char, 32> buf{};
  std::snprintf(buf.data(), buf.size(), "%g", value);
  return buf.data();
}

// ---------------------------------------------------------------- frame

Vec2 Frame::toPixel(const Vec2& d) const {
  auto t = [](double v, double lo, double hi, Scale s) {
    if (s == Scale::Log10)
      return (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
    return (v - lo) / (hi - lo);
  };
  return {left_px + t(d.x(), x_min, x_max, x_scale) * width_px,
          top_px + (1.0 - t(d.y(), y_min, y_max, y_scale)) * height_px};
}

// ---------------------------------------------------------------- panel

Panel::Panel(double x_px, double y_px, double w_px, double h_px, PanelOptions options)
    : x_px_(x_px), y_px_(y_px), w_px_(w_px), h_px_(h_px), options_(std::move(options)) {}

void Panel::polyline(const std::vector<Vec2>& points, const Style& style,
                     const std::string& label) {
  items_.push_back({Kind::Polyline, points, style, {}, {}});
  if (!label.empty()) legend_.push_back({label, style, LegendKind::Line});
}

void Panel::polygon(const std::vector<Vec2>& points, const Style& style, const std::string& label) {
  items_.push_back({Kind::Polygon, points, style, {}, {}});
  if (!label.empty()) legend_.push_back({label, style, LegendKind::Patch});
}

void Panel::polygons(const std::vector<std::vector<Vec2>>& polygons, const Style& style,
                     const std::string& label) {
  std::vector<Vec2> rings;
  for (const auto& ring : polygons) {
    rings.insert(rings.end(), ring.begin(), ring.end());
    rings.emplace_back(
        Vec2::Constant(std::numeric_limits<double>::quiet_NaN()));  // pen up: the next ring
  }
  items_.push_back({Kind::Polygons, rings, style, {}, {}});
  if (!label.empty()) legend_.push_back({label, style, LegendKind::Patch});
}

void Panel::markers(const std::vector<Vec2>& points, const Style& style, const std::string& label) {
  items_.push_back({Kind::Markers, points, style, {}, {}});
  if (!label.empty()) legend_.push_back({label, style, LegendKind::Marker});
}

void Panel::text(const Vec2& at, const std::string& text, const TextStyle& style) {
  items_.push_back({Kind::Text, {at}, Style{}, text, style});
}

void Panel::legendEntry(const LegendEntry& entry) { legend_.push_back(entry); }

Frame Panel::frame() const {
  const bool axes = options_.axes;
  const double top = options_.title.empty() ? (axes ? 10.0 : 4.0) : 30.0;
  const double left = axes ? (options_.y.label.empty() ? 50.0 : 70.0) : 4.0;
  const double bottom = axes ? (options_.x.label.empty() ? 28.0 : 50.0) : 4.0;
  const double right = axes ? 16.0 : 4.0;
  Frame f;
  f.left_px = x_px_ + left;
  f.top_px = y_px_ + top;
  f.width_px = std::max(w_px_ - left - right, 1.0);
  f.height_px = std::max(h_px_ - top - bottom, 1.0);
  f.x_scale = options_.x.scale;
  f.y_scale = options_.y.scale;

  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  bool any_x = false, any_y = false;
  for (const auto& it : items_) {
    for (const auto& p : it.points) {
      if (usable(p.x(), f.x_scale) && usable(p.y(), f.y_scale)) {
        x0 = std::min(x0, p.x());
        x1 = std::max(x1, p.x());
        y0 = std::min(y0, p.y());
        y1 = std::max(y1, p.y());
        any_x = any_y = true;
      }
    }
  }
  axisRange(x0, x1, any_x, options_.x, f.x_min, f.x_max);
  axisRange(y0, y1, any_y, options_.y, f.y_min, f.y_max);

  if (options_.equal_aspect && f.x_scale == Scale::Linear && f.y_scale == Scale::Linear) {
    const double s = std::min(f.width_px / (f.x_max - f.x_min), f.height_px / (f.y_max - f.y_min));
    const double cx = 0.5 * (f.x_min + f.x_max), cy = 0.5 * (f.y_min + f.y_max);
    const double hx = 0.5 * f.width_px / s, hy = 0.5 * f.height_px / s;
    f.x_min = cx - hx;
    f.x_max = cx + hx;
    f.y_min = cy - hy;
    f.y_max = cy + hy;
  }
  return f;
}

// ---------------------------------------------------------------- panel drawing

namespace {

/// True if a data point can be placed on the frame (finite, and > 0 on a log axis).
bool usablePoint(const Frame& f, const Vec2& p) {
  return usable(p.x(), f.x_scale) && usable(p.y(), f.y_scale);
}

/// True for the two corners on the right of the plot area.
bool onRight(Corner c) { return c == Corner::TopRight || c == Corner::BottomRight; }
/// True for the two corners at the bottom of the plot area.
bool onBottom(Corner c) { return c == Corner::BottomLeft || c == Corner::BottomRight; }

/// Fills the plot area with the panel's background colour.
void fillPlotArea(cairo_t* cr, const Frame& f, const Color& background) {
  cairo_rectangle(cr, f.left_px, f.top_px, f.width_px, f.height_px);
  setColor(cr, background);
  cairo_fill(cr);
}

/// Light grid lines across the plot area at the ticks (data units), on whole pixels.
void drawGrid(cairo_t* cr, const Frame& f, const std::vector<double>& xt,
              const std::vector<double>& yt) {
  const double L = f.left_px, T = f.top_px, W = f.width_px, H = f.height_px;
  applyLine(cr, lineStyle(Color::rgb(225, 225, 225), 0.8));
  for (double v : xt) {
    const double px = std::round(f.toPixel({v, f.y_min}).x()) + 0.5;
    cairo_move_to(cr, px, T);
    cairo_line_to(cr, px, T + H);
  }
  for (double v : yt) {
    const double py = std::round(f.toPixel({f.x_min, v}).y()) + 0.5;
    cairo_move_to(cr, L, py);
    cairo_line_to(cr, L + W, py);
  }
  cairo_stroke(cr);
}

/// A long solid polyline stroked as its distinct half-pixel segments.
/// A long path seen edge-on (a boustrophedon from the side) retraces the same pixels
/// hundreds of times, and Cairo's stroker slows down on so many overlaps: each
/// distinct segment is drawn once, as its own sub-path (round caps and joins make
/// the union look the same).
void strokeDistinctSegments(cairo_t* cr, const Frame& f, const std::vector<Vec2>& points,
                            const Style& style) {
  std::unordered_set<std::pair<std::uint64_t, std::uint64_t>, CellPairHash> drawn;
  auto half = [](double v) { return std::clamp(std::round(2.0 * v), -1e9, 1e9); };
  for (std::size_t i = 1; i < points.size(); ++i) {
    if (!usablePoint(f, points[i - 1]) || !usablePoint(f, points[i])) continue;
    const Vec2 a = f.toPixel(points[i - 1]), b = f.toPixel(points[i]);
    std::array<double, 4> s{half(a.x()), half(a.y()), half(b.x()), half(b.y())};
    if (std::make_pair(s[2], s[3]) < std::make_pair(s[0], s[1])) s = {s[2], s[3], s[0], s[1]};
    if (!drawn.insert({cellKey(s[0], s[1]), cellKey(s[2], s[3])}).second) continue;
    cairo_move_to(cr, 0.5 * s[0], 0.5 * s[1]);
    cairo_line_to(cr, 0.5 * s[2], 0.5 * s[3]);
  }
  applyLine(cr, style);
  cairo_stroke(cr);
}

/// How drawPath joins its points.
enum class PathShape {
  Open,    ///< a polyline
  Closed,  ///< one polygon
  Rings,   ///< polygons separated by unusable (NaN) points
};

/// A polyline or polygon(s): closed shapes are closed and filled (if the style has a
/// fill), then the outline is stroked. An unusable point lifts the pen (for Rings it
/// first closes the ring before it).
void drawPath(cairo_t* cr, const Frame& f, const std::vector<Vec2>& points, const Style& style,
              PathShape shape) {
  bool pen = false;
  std::size_t n = 0;
  for (const auto& p : points) {
    if (!usablePoint(f, p)) {
      if (pen && shape == PathShape::Rings) cairo_close_path(cr);
      pen = false;
      continue;
    }
    const Vec2 q = f.toPixel(p);
    if (pen) {
      cairo_line_to(cr, q.x(), q.y());
    } else {
      cairo_move_to(cr, q.x(), q.y());
    }
    pen = true;
    ++n;
  }
  if (n == 0) return;
  if (shape != PathShape::Open) {
    if (pen) cairo_close_path(cr);
    if (style.fill) {
      setColor(cr, *style.fill);
      cairo_fill_preserve(cr);
    }
  }
  if (style.line_width_px > 0.0) {
    applyLine(cr, style);
    cairo_stroke(cr);
  } else {
    cairo_new_path(cr);
  }
}

/// Markers at the points, thinned to one per cell of half a pixel (filled markers) or
/// half a marker (outlined ones): a dense cloud puts thousands of points on one pixel,
/// and Cairo takes minutes to fill and stroke their overlapping outlines on the
/// bridge; thinned so, the picture moves by at most a quarter of a cell.
void drawMarkers(cairo_t* cr, const Frame& f, const std::vector<Vec2>& points, const Style& style) {
  const double cell_px =
      style.line_width_px > 0.0 ? std::max(0.5, 0.5 * style.marker_size_px) : 0.5;
  std::unordered_set<std::uint64_t> drawn;
  for (const auto& p : points) {
    if (!usablePoint(f, p)) continue;
    const Vec2 q = f.toPixel(p);
    const double sx = std::round(q.x() / cell_px), sy = std::round(q.y() / cell_px);
    if (!(std::abs(sx) < 1e9 && std::abs(sy) < 1e9)) continue;  // far outside the clip
    if (!drawn.insert(cellKey(sx, sy)).second) continue;
    markerPath(cr, style.marker, cell_px * sx, cell_px * sy, style.marker_size_px);
  }
  finishMarkers(cr, style);
}

/// Text anchored at a data point (nothing if the point is unusable).
void drawTextAt(cairo_t* cr, const Frame& f, const Vec2& at, const std::string& text,
                const TextStyle& style) {
  if (!usablePoint(f, at)) return;
  const Vec2 q = f.toPixel(at);
  drawText(cr, q.x(), q.y(), text, style);
}

/// The frame of the plot area, tick marks with their labels, and the axis labels.
/// panel_left_px: the panel's left edge, where the y label goes [px].
void drawAxes(cairo_t* cr, const Frame& f, const PanelOptions& options, double panel_left_px,
              const std::vector<double>& xt, const std::vector<double>& yt) {
  const double L = f.left_px, T = f.top_px, W = f.width_px, H = f.height_px;
  const TextStyle tick_style{11.0, Color::rgb(60, 60, 60), Align::Center};
  applyLine(cr, lineStyle(Color::rgb(90, 90, 90), 1.0));
  cairo_rectangle(cr, L + 0.5, T + 0.5, W - 1.0, H - 1.0);
  cairo_stroke(cr);
  for (double v : xt) {
    const double px = f.toPixel({v, f.y_min}).x();
    cairo_move_to(cr, px, T + H);
    cairo_line_to(cr, px, T + H + 4.0);
    drawText(cr, px, T + H + 17.0, tickLabel(v), tick_style);
  }
  for (double v : yt) {
    const double py = f.toPixel({f.x_min, v}).y();
    cairo_move_to(cr, L, py);
    cairo_line_to(cr, L - 4.0, py);
    drawText(cr, L - 7.0, py + 4.0, tickLabel(v), TextStyle{11.0, tick_style.color, Align::Right});
  }
  applyLine(cr, lineStyle(Color::rgb(90, 90, 90), 1.0));
  cairo_stroke(cr);
  drawText(cr, L + W / 2.0, T + H + 38.0, options.x.label, TextStyle{13.0, kBlack, Align::Center});
  drawText(cr, panel_left_px + 17.0, T + H / 2.0, options.y.label,
           TextStyle{13.0, kBlack, Align::Center, false, true});
}

/// A two-tone scale bar in a corner of the plot area: the largest 1/2/5 × 10^k length
/// under a quarter of the width, labelled with `unit`. Linear x axes only.
void drawScaleBar(cairo_t* cr, const Frame& f, Corner corner, const std::string& unit) {
  const double L = f.left_px, T = f.top_px, W = f.width_px, H = f.height_px;
  const double len = roundDown125(0.25 * (f.x_max - f.x_min));
  const double px_len = len * W / (f.x_max - f.x_min);
  const double bx = onRight(corner) ? L + W - 16.0 - px_len : L + 16.0;
  const double by = onBottom(corner) ? T + H - 18.0 : T + 30.0;
  cairo_rectangle(cr, bx - 6.0, by - 22.0, px_len + 12.0, 32.0);
  setColor(cr, kWhite.withAlpha(0.8));
  cairo_fill(cr);
  for (int k = 0; k < 2; ++k) {
    cairo_rectangle(cr, bx + k * px_len / 2.0, by, px_len / 2.0, 6.0);
    setColor(cr, k == 0 ? kBlack : kWhite);
    cairo_fill_preserve(cr);
    applyLine(cr, lineStyle(kBlack, 1.0));
    cairo_stroke(cr);
  }
  drawText(cr, bx + px_len / 2.0, by - 5.0, tickLabel(len) + " " + unit,
           TextStyle{12.0, kBlack, Align::Center, true});
}

/// The legend box 8 px inside a corner of the plot area.
void drawPanelLegend(cairo_t* cr, const Frame& f, Corner corner,
                     const std::vector<LegendEntry>& entries) {
  const double L = f.left_px, T = f.top_px, W = f.width_px, H = f.height_px;
  const Vec2 size = legendSize(cr, entries, 12.0);
  drawLegend(cr, onRight(corner) ? L + W - 8.0 - size.x() : L + 8.0,
             onBottom(corner) ? T + H - 8.0 - size.y() : T + 8.0, entries, 12.0);
}

}  // namespace

void Panel::draw(void* cairo) const {
  cairo_t* cr = ctx(cairo);
  const Frame f = frame();
  const double L = f.left_px, T = f.top_px, W = f.width_px, H = f.height_px;

  cairo_save(cr);
  fillPlotArea(cr, f, options_.background);
  const auto xt = ticks(f.x_min, f.x_max, f.x_scale, std::max(2, static_cast<int>(W / 110.0)));
  const auto yt = ticks(f.y_min, f.y_max, f.y_scale, std::max(2, static_cast<int>(H / 70.0)));
  if (options_.grid) drawGrid(cr, f, xt, yt);

  cairo_rectangle(cr, L, T, W, H);
  cairo_clip(cr);
  for (const auto& it : items_) {
    switch (it.kind) {
      case Kind::Polyline:
        if (!it.style.dashed && it.points.size() > 64) {
          strokeDistinctSegments(cr, f, it.points, it.style);
        } else {
          drawPath(cr, f, it.points, it.style, PathShape::Open);
        }
        break;
      case Kind::Polygon:
        drawPath(cr, f, it.points, it.style, PathShape::Closed);
        break;
      case Kind::Polygons:
        drawPath(cr, f, it.points, it.style, PathShape::Rings);
        break;
      case Kind::Markers:
        drawMarkers(cr, f, it.points, it.style);
        break;
      case Kind::Text:
        drawTextAt(cr, f, it.points.front(), it.text, it.text_style);
        break;
    }
  }
  cairo_reset_clip(cr);

  if (options_.axes) drawAxes(cr, f, options_, x_px_, xt, yt);
  drawText(cr, L + W / 2.0, y_px_ + 20.0, options_.title,
           TextStyle{15.0, kBlack, Align::Center, true});
  if (options_.scale_bar != Corner::None && f.x_scale == Scale::Linear)
    drawScaleBar(cr, f, options_.scale_bar, options_.scale_bar_unit);
  if (options_.legend != Corner::None && !legend_.empty())
    drawPanelLegend(cr, f, options_.legend, legend_);
  cairo_restore(cr);
}

// ---------------------------------------------------------------- figure

Figure::Figure(int width_px, int height_px, const Color& background)
    : width_px_(width_px), height_px_(height_px), background_(background) {
  require(width_px >= 1 && width_px <= 16384, "figure",
          "width must be in [1, 16384] px, got " + std::to_string(width_px));
  require(height_px >= 1 && height_px <= 16384, "figure",
          "height must be in [1, 16384] px, got " + std::to_string(height_px));
}

Panel& Figure::addPanel(double x_px, double y_px, double w_px, double h_px,
                        const PanelOptions& options) {
  panels_.push_back(Panel(x_px, y_px, w_px, h_px, options));
  return panels_.back();
}

void Figure::text(double x_px, double y_px, const std::string& text, const TextStyle& style) {
  // {kind, x, y, w, h, text, text_style, style, entries}
  items_.push_back(Item{Kind::Text, x_px, y_px, 0.0, 0.0, text, style, Style{}, {}});
}

void Figure::rectangle(double x_px, double y_px, double w_px, double h_px, const Style& style) {
  items_.push_back(Item{Kind::Rectangle, x_px, y_px, w_px, h_px, {}, TextStyle{}, style, {}});
}

void Figure::legend(double x_px, double y_px, const std::vector<LegendEntry>& entries,
                    double size_px) {
  TextStyle text_style;
  text_style.size_px = size_px;
  items_.push_back(Item{Kind::Legend, x_px, y_px, 0.0, 0.0, {}, text_style, Style{}, entries});
}

void Figure::draw(void* cairo) const {
  releaseCairoAtExit();
  cairo_t* cr = ctx(cairo);
  cairo_rectangle(cr, 0, 0, width_px_, height_px_);
  setColor(cr, background_);
  cairo_fill(cr);
  for (const auto& p : panels_) p.draw(cr);
  for (const auto& it : items_) {
    switch (it.kind) {
      case Kind::Text:
        drawText(cr, it.x, it.y, it.text, it.text_style);
        break;
      case Kind::Rectangle:
        cairo_rectangle(cr, it.x, it.y, it.w, it.h);
        if (it.style.fill) {
          setColor(cr, *it.style.fill);
          cairo_fill_preserve(cr);
        }
        if (it.style.line_width_px > 0.0) {
          applyLine(cr, it.style);
          cairo_stroke(cr);
        } else {
          cairo_new_path(cr);
        }
        break;
      case Kind::Legend:
        drawLegend(cr, it.x, it.y, it.entries, it.text_style.size_px);
        break;
    }
  }
}

std::string Figure::png() const {
  SurfacePtr surface(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width_px_, height_px_),
                     &cairo_surface_destroy);
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error("render: cannot create a " + std::to_string(width_px_) + "x" +
                             std::to_string(height_px_) + " image");
  {
    ContextPtr cr(cairo_create(surface.get()), &cairo_destroy);
    draw(cr.get());
  }
  std::string bytes;
  if (cairo_surface_write_to_png_stream(surface.get(), &appendToString, &bytes) !=
      CAIRO_STATUS_SUCCESS)
    throw std::runtime_error("render: PNG encoding failed");
  return bytes;
}

std::string Figure::svg() const {
  std::string bytes;
  {
    SurfacePtr surface(
        cairo_svg_surface_create_for_stream(&appendToString, &bytes, width_px_, height_px_),
        &cairo_surface_destroy);
    {
      ContextPtr cr(cairo_create(surface.get()), &cairo_destroy);
      draw(cr.get());
    }
    cairo_surface_finish(surface.get());
    if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
      throw std::runtime_error("render: SVG encoding failed");
  }
  return bytes;
}

void Figure::writePng(const std::string& path) const { writeBytes(path, png()); }
void Figure::writeSvg(const std::string& path) const { writeBytes(path, svg()); }

// ---------------------------------------------------------------- raster

Color Raster::at(int x, int y) const {
  if (x < 0 || y < 0 || x >= width || y >= height)
    throw std::out_of_range("raster: pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                            ") off the image");
  const unsigned int v = argb[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                              static_cast<std::size_t>(x)];
  const double a = ((v >> 24) & 0xFFu) / 255.0;
  auto comp = [&](unsigned int shift) {
    const double c = ((v >> shift) & 0xFFu) / 255.0;
    return a > 0.0 ? std::min(c / a, 1.0) : 0.0;
  };
  return {comp(16), comp(8), comp(0), a};
}

Raster decodePng(const std::string& bytes) {
  ReadCursor cursor{&bytes, 0};
  SurfacePtr surface(cairo_image_surface_create_from_png_stream(&readFromString, &cursor),
                     &cairo_surface_destroy);
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error(std::string("not a PNG image: ") +
                             cairo_status_to_string(cairo_surface_status(surface.get())));
  cairo_surface_flush(surface.get());
  Raster r;
  r.width = cairo_image_surface_get_width(surface.get());
  r.height = cairo_image_surface_get_height(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  const cairo_format_t format = cairo_image_surface_get_format(surface.get());
  const unsigned char* data = cairo_image_surface_get_data(surface.get());
  r.argb.resize(static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height));
  for (int y = 0; y < r.height; ++y) {
    for (int x = 0; x < r.width; ++x) {
      std::uint32_t v = 0;
      std::memcpy(
          &v, data + static_cast<std::ptrdiff_t>(y) * stride + 4 * static_cast<std::ptrdiff_t>(x),
          4);
      if (format != CAIRO_FORMAT_ARGB32) v |= 0xFF000000u;  // RGB24: opaque
      r.argb[static_cast<std::size_t>(y) * static_cast<std::size_t>(r.width) +
             static_cast<std::size_t>(x)] = v;
    }
  }
  return r;
}

}  // namespace uavip::render
