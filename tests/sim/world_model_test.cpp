// Tests of sim/world_model clutter primitives: trees and grass are small boxes
// (obstacles, never a surface of 2 m² or more), placed as documented, seeded.
#include "uavip/sim/world_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "uavip/core/error.h"

namespace uavip::sim {
namespace {

TEST(Tree, TrunkAndCrownBoxesInTheirPlaces) {
  WorldModel w;
  TreeOptions o;
  o.crown_boxes = 10;
  o.seed = 4;
  w.addTree("t", Vec3(3, 4, 1), o);
  ASSERT_EQ(w.rects().size(), 6u * 11u);
  const Vec3 crown(3, 4, 1 + o.trunk_height_m + o.crown_radius_m);
  for (const Rect& r : w.rects()) {
    EXPECT_LT(r.area(), 2.0) << r.name;
    const std::string n = r.name;
    if (n.rfind("t/trunk/", 0) == 0) {
      // Trunk faces: inside the trunk box.
      const Vec3 c = r.center();
      EXPECT_LE(std::abs(c.x() - 3), o.trunk_width_m / 2 + 1e-12);
      EXPECT_LE(std::abs(c.y() - 4), o.trunk_width_m / 2 + 1e-12);
      EXPECT_GE(c.z(), 1 - 1e-12);
      EXPECT_LE(c.z(), 1 + o.trunk_height_m + 1e-12);
    } else {
      ASSERT_EQ(n.rfind("t/crown", 0), 0u) << n;
      // A crown face centre lies within the crown radius + half a cube of the crown centre.
      EXPECT_LE((r.center() - crown).norm(), o.crown_radius_m + 0.5 * o.crown_box_m + 1e-12) << n;
    }
  }
  // Every box piece stays well under the 2 m² surface threshold, and so does the
  // tree's whole extent seen from the side (trunk height x crown width).
  EXPECT_LT(o.trunk_width_m * o.trunk_height_m + std::pow(2 * o.crown_radius_m + o.crown_box_m, 2),
            2.0);
}

TEST(Tree, SeededLayout) {
  WorldModel a, b, c;
  TreeOptions o;
  a.addTree("t", Vec3::Zero(), o);
  b.addTree("t", Vec3::Zero(), o);
  o.seed = 99;
  c.addTree("t", Vec3::Zero(), o);
  ASSERT_EQ(a.rects().size(), b.rects().size());
  bool differs = false;
  for (std::size_t i = 0; i < a.rects().size(); ++i) {
    EXPECT_EQ(a.rects()[i].corner, b.rects()[i].corner);
    differs = differs || a.rects()[i].corner != c.rects()[i].corner;
  }
  EXPECT_TRUE(differs);
}

TEST(Grass, TuftsInsideThePatch) {
  WorldModel w;
  GrassOptions o;
  o.size_x_m = 3.0;
  o.size_y_m = 1.0;
  o.tufts = 20;
  w.addGrass("g", Vec3(10, -2, 0.5), o);
  ASSERT_EQ(w.rects().size(), 120u);
  for (const Rect& r : w.rects()) {
    const Vec3 c = r.center();
    EXPECT_LE(std::abs(c.x() - 10), 1.5 + o.tuft_width_m);
    EXPECT_LE(std::abs(c.y() + 2), 0.5 + o.tuft_width_m);
    EXPECT_GE(c.z(), 0.5 - 1e-12);
    EXPECT_LE(c.z(), 0.5 + o.tuft_height_m + 1e-12);
    EXPECT_LT(r.area(), 0.1);
  }
}

TEST(Clutter, BadOptionsNameTheField) {
  WorldModel w;
  TreeOptions t;
  t.trunk_height_m = 0.0;
  try {
    w.addTree("t", Vec3::Zero(), t);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("trunk_height_m"), std::string::npos) << e.what();
  }
  GrassOptions g;
  g.tufts = 0;
  try {
    w.addGrass("g", Vec3::Zero(), g);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tufts"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(w.empty());
}

}  // namespace
}  // namespace uavip::sim
