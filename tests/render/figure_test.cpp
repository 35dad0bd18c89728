// The rendering module: tick values, the data→pixel frame, and pixels read back
// from the encoded PNG at places computed by hand.

#include "uavip/render/figure.h"

#include <gtest/gtest.h>

#include <cmath>

#include "uavip/core/error.h"
#include "uavip/render/plot.h"

namespace {

using uavip::render::Color;
using uavip::render::Figure;
using uavip::render::PanelOptions;
using uavip::render::Scale;
using uavip::render::Vec2;
namespace render = uavip::render;

bool near(const Color& a, const Color& b, double tol = 0.02) {
  return std::abs(a.r - b.r) < tol && std::abs(a.g - b.g) < tol && std::abs(a.b - b.b) < tol;
}

std::size_t countNot(const render::Raster& r, const Color& background) {
  std::size_t n = 0;
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x) n += !near(r.at(x, y), background, 0.01);
  return n;
}

TEST(Ticks, LinearStepsAreOneTwoFiveTimesAPowerOfTen) {
  // 0..1 in about 5 steps: step 0.2 (1/5 rounds to 2 × 10^-1).
  const auto t = render::ticks(0.0, 1.0, Scale::Linear, 5);
  ASSERT_EQ(t.size(), 6u);
  for (std::size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(t[i], 0.2 * static_cast<double>(i), 1e-12);
  // -3.3..7.1, about 4 ticks: raw step 2.6 → 2; first tick −2, last 6.
  const auto u = render::ticks(-3.3, 7.1, Scale::Linear, 4);
  EXPECT_NEAR(u.front(), -2.0, 1e-12);
  EXPECT_NEAR(u.back(), 6.0, 1e-12);
  EXPECT_NEAR(u[1] - u[0], 2.0, 1e-12);
  EXPECT_TRUE(render::ticks(1.0, 1.0, Scale::Linear).empty());
}

TEST(Ticks, LogTicksArePowersOfTen) {
  const auto t = render::ticks(0.003, 250.0, Scale::Log10);
  const std::vector<double> expected{0.01, 0.1, 1.0, 10.0, 100.0};
  ASSERT_EQ(t.size(), expected.size());
  for (std::size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(t[i], expected[i], expected[i] * 1e-9);
  // Under two decades: 1, 2, 5 × 10^k.
  const auto d = render::ticks(1.5, 30.0, Scale::Log10);
  const std::vector<double> dense{2.0, 5.0, 10.0, 20.0};
  ASSERT_EQ(d.size(), dense.size());
  for (std::size_t i = 0; i < d.size(); ++i) EXPECT_NEAR(d[i], dense[i], 1e-9);
  EXPECT_TRUE(render::ticks(-1.0, 10.0, Scale::Log10).empty());
  EXPECT_EQ(render::tickLabel(0.25), "0.25");
  EXPECT_EQ(render::tickLabel(1000.0), "1000");
}

TEST(Frame, FixedRangeMapsCornersToThePlotArea) {
  Figure fig(400, 300);
  PanelOptions o;
  o.axes = false;
  o.x.min = 0.0;
  o.x.max = 10.0;
  o.y.min = -5.0;
  o.y.max = 5.0;
  auto& p = fig.addPanel(0, 0, 400, 300, o);
  const render::Frame f = p.frame();
  const Vec2 a = f.toPixel({0.0, -5.0});
  const Vec2 b = f.toPixel({10.0, 5.0});
  EXPECT_NEAR(a.x(), f.left_px, 1e-9);
  EXPECT_NEAR(a.y(), f.top_px + f.height_px, 1e-9);  // data y up, pixel y down
  EXPECT_NEAR(b.x(), f.left_px + f.width_px, 1e-9);
  EXPECT_NEAR(b.y(), f.top_px, 1e-9);
  EXPECT_NEAR(f.toPixel({5.0, 0.0}).x(), f.left_px + f.width_px / 2.0, 1e-9);
}

TEST(Frame, EqualAspectGivesTheSamePixelsPerUnitOnBothAxes) {
  Figure fig(900, 300);
  PanelOptions o;
  o.equal_aspect = true;
  auto& p = fig.addPanel(0, 0, 900, 300, o);
  p.polyline({{0.0, 0.0}, {2.0, 4.0}}, render::lineStyle(render::kBlack));
  const render::Frame f = p.frame();
  const Vec2 o0 = f.toPixel({0.0, 0.0});
  const double px_per_x = f.toPixel({1.0, 0.0}).x() - o0.x();
  const double px_per_y = o0.y() - f.toPixel({0.0, 1.0}).y();
  EXPECT_NEAR(px_per_x, px_per_y, 1e-9);
  // The data (height 4 + 5 % margins) fills the panel height, not more.
  EXPECT_LE(f.y_min, 0.0);
  EXPECT_GE(f.y_max, 4.0);
  EXPECT_NEAR(f.y_max - f.y_min, 4.4, 1e-9);
}

TEST(Frame, LogAxisSpacesDecadesEvenlyAndDropsNonPositiveValues) {
  Figure fig(500, 400);
  PanelOptions o;
  o.y.scale = Scale::Log10;
  auto& p = fig.addPanel(0, 0, 500, 400, o);
  p.markers({{1.0, 0.01}, {2.0, 1.0}, {3.0, 100.0}, {4.0, 0.0}, {5.0, -3.0}},
            render::markerStyle(render::palette(0)));
  const render::Frame f = p.frame();
  const double y1 = f.toPixel({1.0, 0.01}).y(), y2 = f.toPixel({1.0, 1.0}).y(),
               y3 = f.toPixel({1.0, 100.0}).y();
  EXPECT_NEAR(y1 - y2, y2 - y3, 1e-9);
  EXPECT_GT(f.y_min, 0.0);
  // x range from the kept points only (1..3 with margins).
  EXPECT_LT(f.x_max, 3.5);
  EXPECT_NO_THROW(fig.png());
}

TEST(Figure, PixelsAppearWhereTheFrameSays) {
  Figure fig(300, 200);
  PanelOptions o;
  o.axes = false;
  o.grid = false;
  o.x.min = 0.0;
  o.x.max = 10.0;
  o.y.min = 0.0;
  o.y.max = 10.0;
  auto& p = fig.addPanel(0, 0, 300, 200, o);
  const Color red = Color::rgb(200, 0, 0);
  const Color blue = Color::rgb(0, 0, 200);
  p.polyline({{1.0, 5.0}, {9.0, 5.0}}, render::lineStyle(red, 6.0));
  p.polygon({{6.0, 7.0}, {8.0, 7.0}, {8.0, 9.0}, {6.0, 9.0}}, render::patchStyle(blue, blue));
  const render::Raster img = render::decodePng(fig.png());
  ASSERT_EQ(img.width, 300);
  ASSERT_EQ(img.height, 200);
  const render::Frame f = p.frame();
  const Vec2 on_line = f.toPixel({5.0, 5.0});
  EXPECT_TRUE(near(img.at(static_cast<int>(on_line.x()), static_cast<int>(on_line.y())), red));
  const Vec2 in_square = f.toPixel({7.0, 8.0});
  EXPECT_TRUE(near(img.at(static_cast<int>(in_square.x()), static_cast<int>(in_square.y())), blue));
  const Vec2 empty = f.toPixel({3.0, 2.0});
  EXPECT_TRUE(
      near(img.at(static_cast<int>(empty.x()), static_cast<int>(empty.y())), render::kWhite));
  EXPECT_THROW(img.at(300, 0), std::out_of_range);
}

TEST(Figure, LegendTextAndScaleBarAddInk) {
  auto make = [](bool extras) {
    Figure fig(400, 300);
    PanelOptions o;
    o.axes = false;
    o.grid = false;
    o.equal_aspect = true;
    if (extras) {
      o.scale_bar = render::Corner::BottomLeft;
      o.title = "title";
    }
    auto& p = fig.addPanel(0, 0, 400, 300, o);
    p.polyline({{0.0, 0.0}, {10.0, 3.0}}, render::lineStyle(render::kBlack),
               extras ? "a line" : "");
    return countNot(render::decodePng(fig.png()), render::kWhite);
  };
  EXPECT_GT(make(true), make(false) + 200);
}

TEST(Figure, SvgIsAnSvgDocumentOfTheFigureSize) {
  Figure fig(320, 240);
  auto& p = fig.addPanel(0, 0, 320, 240, PanelOptions{});
  p.markers({{0.0, 0.0}, {1.0, 1.0}},
            render::markerStyle(render::palette(1), render::Marker::Square));
  fig.text(10, 20, "hello");
  const std::string svg = fig.svg();
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("320"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
}

TEST(Figure, RejectsBadSizesAndBadPng) {
  EXPECT_THROW(Figure(0, 10), uavip::InputError);
  EXPECT_THROW(Figure(10, 20000), uavip::InputError);
  EXPECT_THROW(render::decodePng("not a png"), std::runtime_error);
}

TEST(Plot, ScatterWithLogAxisDrawsEverySeries) {
  std::vector<render::Series> s(2);
  s[0].label = "astar";
  s[0].x = {30.0, 31.0, 32.0};
  s[0].y = {0.01, 0.02, 0.05};
  s[1].label = "rrt";
  s[1].x = {35.0, 36.0};
  s[1].y = {1.0, 3.0};
  s[1].lines = true;
  s[1].color = Color::rgb(200, 0, 0);
  render::PlotOptions o;
  o.title = "time vs length";
  o.x.label = "path length [m]";
  o.y = {"time [s]", Scale::Log10, {}, {}};
  const Figure fig = render::plot(s, o);
  const render::Raster img = render::decodePng(fig.png());
  EXPECT_EQ(img.width, o.width_px);
  EXPECT_EQ(img.height, o.height_px);
  // Some pixels have the second series' red (its markers and line).
  std::size_t red = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) red += near(img.at(x, y), Color::rgb(200, 0, 0), 0.03);
  EXPECT_GT(red, 20u);
  s[0].y.pop_back();
  EXPECT_THROW(render::plot(s, o), uavip::InputError);
}

}  // namespace
