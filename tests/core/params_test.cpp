// Parameter tables (core/params.h): the precedence of the layers, the bounds as text
// and as checks, and a table lifted into an outer struct reaching the same fields.

#include "uavip/core/params.h"

#include <gtest/gtest.h>

namespace uavip::params {
namespace {

struct Inner {
  double width_m{2.0};
  int count{3};
  std::string kind{"a"};
  std::optional<double> limit_m;
};

struct Outer {
  Inner inner;
  Vec3 at{1.0, 2.0, 3.0};
};

Table<Inner> innerTable() {
  Table<Inner> t;
  t.add("width_m", &Inner::width_m, "a width").unitIs("m").positive().mayBeAuto();
  t.add("count", &Inner::count, "a count").within(1, 5);
  t.add("kind", &Inner::kind, "a kind").oneOf({"a", "b"});
  t.add("limit_m", &Inner::limit_m, "an optional limit").atLeast(0);
  return t;
}

TEST(Params, HigherLayersWinWhateverTheOrder) {
  Sources s;
  EXPECT_EQ(s.of("x.k"), Source::Default);
  EXPECT_TRUE(s.set("x.k", Source::File));
  EXPECT_FALSE(s.set("x.k", Source::Auto));  // auto never overrides the file
  EXPECT_FALSE(s.set("x.k", Source::Profile));
  EXPECT_TRUE(s.fromFile("x.k"));
  EXPECT_TRUE(s.set("x.j", Source::Profile));
  EXPECT_TRUE(s.set("x.j", Source::Auto));  // auto overrides a profile
  EXPECT_EQ(s.of("x.j"), Source::Auto);
  EXPECT_TRUE(s.anyFromFile("x."));
  EXPECT_FALSE(s.anyFromFile("y."));
  EXPECT_FALSE(s.anyFromFile("x.j"));  // set by auto only
}

TEST(Params, BoundsAsTextAndChecks) {
  const Table<Inner> t = innerTable();
  ASSERT_EQ(t.rows().size(), 4U);
  EXPECT_EQ(t.rows()[0].range(), "> 0");
  EXPECT_EQ(t.rows()[1].range(), "in [1, 5]");
  EXPECT_EQ(t.rows()[3].range(), ">= 0");
  EXPECT_EQ(t.rows()[0].kind, Kind::Number);
  EXPECT_EQ(t.rows()[1].kind, Kind::Integer);
  EXPECT_NE(t.rows()[0].layers & kAuto, 0U);
  EXPECT_EQ(t.rows()[1].layers & kAuto, 0U);

  Inner ok;
  EXPECT_NO_THROW(t.check(ok, "sec"));  // the defaults pass
  Inner bad = ok;
  bad.width_m = 0.0;
  try {
    t.check(bad, "sec");
    FAIL() << "width 0 accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "sec: width_m must be > 0, got 0");
  }
  bad = ok;
  bad.count = 6;
  EXPECT_THROW(t.check(bad, "sec"), InputError);
  bad = ok;
  bad.kind = "c";
  EXPECT_THROW(t.check(bad, "sec"), InputError);
  bad = ok;
  bad.limit_m = -1.0;  // an optional is checked when present
  EXPECT_THROW(t.check(bad, "sec"), InputError);
  bad.limit_m.reset();
  EXPECT_NO_THROW(t.check(bad, "sec"));
  bad.width_m = std::nan("");
  EXPECT_THROW(t.check(bad, "sec"), InputError);
}

TEST(Params, ALiftedTableReachesTheSameFields) {
  Table<Outer> t;
  t.include("sec.", &Outer::inner, innerTable());
  t.add("at", &Outer::at, "a point");
  Outer o;
  ASSERT_EQ(t.rows().size(), 5U);
  EXPECT_EQ(t.rows()[0].key, "sec.width_m");
  EXPECT_EQ(t.find(o, &o.inner.count)->key, "sec.count");
  EXPECT_EQ(t.find(o, &o.at)->key, "at");
  const double elsewhere = 0.0;
  EXPECT_EQ(t.find(o, &elsewhere), nullptr);
  t.rows()[0].set(o, toValue(4.5));
  EXPECT_DOUBLE_EQ(o.inner.width_m, 4.5);
  EXPECT_EQ(t.rows()[4].get(o).numbers, (std::vector<double>{1.0, 2.0, 3.0}));
  t.rows()[3].set(o, toValue(std::optional<double>(7.0)));
  EXPECT_EQ(o.inner.limit_m, 7.0);
}

}  // namespace
}  // namespace uavip::params
