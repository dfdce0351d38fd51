// Scenario bindings on small structs of their own: one declaration gives the schema entry
// (default from the struct, converted to the JSON unit), the reader and the writer, the paths
// of fields for checks, and sentinels; enums take their choices from their name tables.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "trainsim/scenario/binding.hpp"
#include "trainsim/scenario/scenario.hpp"

namespace trainsim::scenario {

enum class Shape { kRound, kSquare, kSecret };
constexpr EnumName<Shape> kShapeNames[] = {
    {Shape::kRound, "round"}, {Shape::kSquare, "square"}, {Shape::kSecret, "secret"}};
constexpr std::span<const EnumName<Shape>> enumNames(Shape) {
  return kShapeNames;
}

namespace {

struct Inner {
  double min_m = 1.0, max_m = 2.0;
};

struct Item {
  double length_m = 500.0;
  double cant_m = -1.0;  // -1: chosen by the rules
};

struct Outer {
  double speed_m_s = 160.0 / 3.6;
  double cant_m = 0.160;
  double grade = 0.0125;
  double range = std::numeric_limits<double>::infinity();  // JSON 0: none
  int count = 3;
  bool on = true;
  std::string label = "x";
  Shape shape = Shape::kSquare;
  Inner inner{5.0, 7.0};  // the parent's defaults win over Inner's own
  std::vector<Item> items{Item{}, Item{250.0, 0.08}};
};

const Binding<Inner>& innerBinding() {
  static const Binding<Inner> b = [] {
    Binding<Inner> i;
    i.number("min_m", &Inner::min_m, units::si("m"), "Smallest").range(0, 100);
    i.number("max_m", &Inner::max_m, units::si("m"), "Largest").range(0, 100);
    i.notAbove(&Inner::min_m, &Inner::max_m);
    return i;
  }();
  return b;
}

const Binding<Item>& itemBinding() {
  static const Binding<Item> b = [] {
    Binding<Item> i;
    i.number("length_m", &Item::length_m, units::si("m"), "Length").range(0, 1e6);
    i.number("cant_mm", &Item::cant_m, units::kMillimetre, "Cant; -1 chooses", Sentinel{-1, -1})
        .range(-1, 250);
    return i;
  }();
  return b;
}

const Binding<Outer>& outerBinding() {
  static const Binding<Outer> b = [] {
    Binding<Outer> o;
    o.number("speed_km_h", &Outer::speed_m_s, units::kKilometrePerHour, "Speed").range(1, 400);
    o.number("cant_mm", &Outer::cant_m, units::kMillimetre, "Cant").range(0, 200);
    o.number("grade_permille", &Outer::grade, units::kPermille, "Grade").range(0, 100);
    o.number("range", &Outer::range, units::kNone, "Range; 0: none",
             Sentinel{0.0, std::numeric_limits<double>::infinity()})
        .range(0, std::nullopt);
    o.integer("count", &Outer::count, "", "Count").range(0, 10);
    o.boolean("on", &Outer::on, "On");
    o.string("label", &Outer::label, "Label");
    o.choice("shape", &Outer::shape, "Shape", {Shape::kSecret});
    o.object("inner", &Outer::inner, innerBinding(), "Inner");
    o.array("items", &Outer::items, itemBinding(), "An item", "Items");
    return o;
  }();
  return b;
}

Schema schemaOf() {
  Schema s;
  s.add(outerBinding().declare("outer", "The outer section"));
  s.addCheck([](const Json& r, std::vector<Problem>& problems) {
    outerBinding().problems(outerBinding().read(r.at("outer")), "outer", problems);
  });
  return s;
}

TEST(Binding, DefaultsComeFromTheStructInTheJsonUnit) {
  const Json d = schemaOf().defaults().at("outer");
  EXPECT_EQ(d.at("speed_km_h").get<double>(), 160.0);  // 12 significant digits: exact
  EXPECT_EQ(d.at("cant_mm").get<double>(), 160.0);
  EXPECT_EQ(d.at("grade_permille").get<double>(), 12.5);
  EXPECT_EQ(d.at("range").get<double>(), 0.0);  // the sentinel for infinity
  EXPECT_EQ(d.at("count").get<int>(), 3);
  EXPECT_EQ(d.at("shape"), "square");
  EXPECT_EQ(d.at("inner").at("min_m").get<double>(), 5.0);  // the parent's value of the field
  ASSERT_EQ(d.at("items").size(), 2u);
  EXPECT_EQ(d.at("items")[0].at("cant_mm").get<double>(), -1.0);
  EXPECT_EQ(d.at("items")[1].at("cant_mm").get<double>(), 80.0);
}

TEST(Binding, ReadingTheDefaultsGivesTheStructBack) {
  const Outer o = outerBinding().read(schemaOf().defaults().at("outer"));
  const Outer ref;
  EXPECT_EQ(o.speed_m_s, ref.speed_m_s);  // 160 / 3.6 as the struct writes it, bit for bit
  EXPECT_EQ(o.cant_m, ref.cant_m);
  EXPECT_EQ(o.grade, ref.grade);
  EXPECT_TRUE(std::isinf(o.range));
  EXPECT_EQ(o.shape, Shape::kSquare);
  EXPECT_EQ(o.inner.max_m, 7.0);
  ASSERT_EQ(o.items.size(), 2u);
  EXPECT_EQ(o.items[0].cant_m, -1.0);
  EXPECT_DOUBLE_EQ(o.items[1].cant_m, 0.08);
  EXPECT_EQ(outerBinding().write(o), schemaOf().defaults().at("outer"));
}

TEST(Binding, ConvertsUnitsWhenReading) {
  Json in = {{"outer",
              {{"speed_km_h", 36.0},
               {"cant_mm", 100.0},
               {"range", 5.0},
               {"items", {{{"cant_mm", 50.0}}}}}}};
  const Schema s = schemaOf();
  const Schema::Resolution r = s.resolve(in);
  ASSERT_TRUE(r.problems.empty()) << r.problems.front().text();
  const Outer o = outerBinding().read(r.resolved.at("outer"));
  EXPECT_DOUBLE_EQ(o.speed_m_s, 10.0);
  EXPECT_DOUBLE_EQ(o.cant_m, 0.1);
  EXPECT_EQ(o.range, 5.0);
  ASSERT_EQ(o.items.size(), 1u);
  EXPECT_EQ(o.items[0].length_m, 500.0);  // the item's omitted field: the item default
  EXPECT_DOUBLE_EQ(o.items[0].cant_m, 0.05);
}

TEST(Binding, EnumChoicesComeFromTheNameTableLessExclusions) {
  const Schema schema = schemaOf();
  const Param* shape = schema.root().field("outer")->field("shape");
  ASSERT_NE(shape, nullptr);
  EXPECT_EQ(shape->choices, (std::vector<std::string>{"round", "square"}));
  const Schema::Resolution r = schema.resolve({{"outer", {{"shape", "secret"}}}});
  ASSERT_EQ(r.problems.size(), 1u);
  EXPECT_EQ(r.problems[0].path, "outer.shape");
}

TEST(Binding, PathsOfFieldsAndChecksNameRealPaths) {
  EXPECT_EQ(outerBinding().pathTo(&Outer::cant_m), "cant_mm");
  EXPECT_EQ(outerBinding().pathTo([](const Outer& o) -> const double& { return o.inner.max_m; }),
            "inner.max_m");
  const Schema::Resolution r = schemaOf().resolve({{"outer", {{"inner", {{"min_m", 9.0}}}}}});
  ASSERT_EQ(r.problems.size(), 1u);
  EXPECT_EQ(r.problems[0].path, "outer.inner.min_m");
  EXPECT_EQ(r.problems[0].message, "must not exceed max_m");
}

TEST(Binding, EmbeddedFieldsSitFlatInTheParent) {
  struct Basics {
    std::string name = "a";
  };
  struct Sensor {
    Basics basics{"gnss"};
    double sigma = 1.5;
  };
  Binding<Basics> basics;
  basics.string("name", &Basics::name, "Name");
  Binding<Sensor> b;
  b.embed(&Sensor::basics, basics);
  b.number("sigma_m", &Sensor::sigma, units::si("m"), "Sigma");
  const Param p = b.declare("sensor", "A sensor");
  ASSERT_EQ(p.fields.size(), 2u);
  EXPECT_EQ(p.fields[0].key, "name");
  EXPECT_EQ(p.fields[0].default_value, "gnss");  // the parent's default
  const Sensor s = b.read({{"name", "rx"}, {"sigma_m", 2.0}});
  EXPECT_EQ(s.basics.name, "rx");
  EXPECT_EQ(b.pathTo([](const Sensor& x) -> const std::string& { return x.basics.name; }), "name");
}

}  // namespace
}  // namespace trainsim::scenario
