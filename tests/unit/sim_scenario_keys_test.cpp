// Parameters declared once: every section reads its struct's defaults back (the schema's
// defaults are the structs'), and a scan of the source (modules/ and app/, outside tests, docs
// and configs/) finds no scenario key read by string (x.at("key"), x["key"], get<T>("path"),
// setValue("path"), …) and no JSON path spelled out where the scenario is read — keys and paths
// come from the bindings — and no JSON path named in a message or description that the schema
// does not have. (Words shared with other formats — railroad.json's "type", trajectory.csv's
// "x_m" — are not scenario reads and are not counted.)

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "trainsim/sim/config.hpp"
#include "trainsim/sim/schema.hpp"

namespace trainsim::sim {
namespace {

// Numbers equal to 1e-12 relative, everything else exactly; `path` names a mismatch.
void expectSameJson(const scenario::Json& a, const scenario::Json& b, const std::string& path) {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>(), y = b.get<double>();
    EXPECT_LE(std::abs(x - y), 1e-12 * std::max(1.0, std::abs(y))) << path;
    return;
  }
  ASSERT_EQ(a.type(), b.type()) << path;
  if (a.is_object()) {
    ASSERT_EQ(a.size(), b.size()) << path;
    for (const auto& [key, value] : a.items())
      expectSameJson(value, b.at(key), path + "." + key);
  } else if (a.is_array()) {
    ASSERT_EQ(a.size(), b.size()) << path;
    for (std::size_t i = 0; i < a.size(); ++i)
      expectSameJson(a[i], b[i], path + "[" + std::to_string(i) + "]");
  } else {
    EXPECT_EQ(a, b) << path;
  }
}

template <typename T>
void expectStructDefaults(const scenario::Section<T>& section) {
  const scenario::Json defaults = scenarioSchema().defaults();
  const T read = section.read(defaults);
  expectSameJson(section.binding.write(read), section.binding.write(section.binding.defaults()),
                 section.key);
}

TEST(ScenarioDefaults, EverySectionReadsItsStructsDefaultsBack) {
  expectStructDefaults(geodeticOriginSection());
  expectStructDefaults(trajectorySection());
  expectStructDefaults(datasetSection());
  expectStructDefaults(routeSection());
  expectStructDefaults(designSection());
  expectStructDefaults(layoutSection());
  expectStructDefaults(trainSection());
  // The track module's own defaults are the ones a default scenario runs with.
  const RouteConfig route = routeSection().read(scenarioSchema().defaults());
  EXPECT_EQ(route.generator.length_m, track::RouteGeneratorParams{}.length_m);
  EXPECT_EQ(route.generator.tunnel.length_max_m, track::RouteGeneratorParams{}.tunnel.length_max_m);
  EXPECT_DOUBLE_EQ(designSection().read(scenarioSchema().defaults()).max_cant_gradient,
                   track::DesignRules{}.max_cant_gradient);
}

TEST(ScenarioDefaults, PathsComeFromTheBindings) {
  EXPECT_EQ(routeSection().path(&RouteConfig::source), "route.source");
  EXPECT_EQ(routeSection().path([](const RouteConfig& c) -> const double& {
    return c.generator.station.length_max_m;
  }),
            "route.generator.station.length_max_m");
  EXPECT_EQ(layoutSection().path(&track::LayoutParams::aux_parallel_min_m),
            "layout.auxiliary.parallel_min_m");
  EXPECT_EQ(samplePeriodPath(), "trajectory.sample_period_ns");
}

// ---------------------------------------------------------------------------------------
// The source scan.

struct Declared {
  std::map<std::string, int> keys;  // key -> how many parameters have it
  std::set<std::string> paths;      // dotted, array items as "list[]"
  std::set<std::string> sections;   // top-level object keys
};

void collect(const scenario::Param& p, const std::string& path, Declared& out) {
  for (const scenario::Param& f : p.fields) {
    const std::string here = path.empty() ? f.key : path + "." + f.key;
    ++out.keys[f.key];
    out.paths.insert(here);
    if (path.empty() && f.type == scenario::ParamType::kObject)
      out.sections.insert(f.key);
    collect(f, here, out);
    if (f.item) {
      out.paths.insert(here + "[]");
      collect(*f.item, here + "[]", out);
    }
  }
}

// A string literal and whether the code reads a JSON value with it: x.at("key"), x["key"],
// x.get<T>("path"), x.contains("key"), x.value("key", …), x.find("key").
struct Literal {
  std::string text;
  bool read = false;
};

// `with_at`: count x.at("…") too (off for the studio, whose .at() reads CSV columns).
bool readContext(const std::string& text, std::size_t quote, bool with_at) {
  std::size_t i = quote;
  while (i > 0 && (text[i - 1] == ' ' || text[i - 1] == '\n'))
    --i;
  const std::string before = text.substr(i >= 10 ? i - 10 : 0, i >= 10 ? 10 : i);
  for (const char* call : {"[", ">(", "contains(", "value(", "find(", "setValue("})
    if (before.ends_with(call))
      return true;
  return with_at && before.ends_with("at(");
}

// The string literals of a C++ file, without those in comments.
std::vector<Literal> literals(const std::string& text, bool with_at) {
  std::vector<Literal> out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {
      i = text.find('\n', i);
      if (i == std::string::npos)
        break;
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      i = text.find("*/", i + 2);
      if (i == std::string::npos)
        break;
      ++i;
    } else if (c == '\'' && i > 0 && std::isalnum(static_cast<unsigned char>(text[i - 1]))) {
      continue;              // a digit separator: 1'000'000
    } else if (c == '\'') {  // a character literal ('"', '\'')
      i = text.find('\'', i + (text[i + 1] == '\\' ? 3 : 2));
      if (i == std::string::npos)
        break;
    } else if (c == '"') {
      Literal lit{{}, readContext(text, i, with_at)};
      for (++i; i < text.size() && text[i] != '"'; ++i) {
        if (text[i] == '\\' && i + 1 < text.size())
          ++i;
        lit.text += text[i];
      }
      out.push_back(std::move(lit));
    }
  }
  return out;
}

std::string withoutIndices(const std::string& s) {
  return std::regex_replace(s, std::regex(R"(\[[^\]]*\])"), "[]");
}

TEST(ScenarioKeys, EachKeyIsSpelledOnceAndEveryPathInAMessageExists) {
  Declared declared;
  collect(scenarioSchema().root(), "", declared);
  ASSERT_GT(declared.paths.size(), 100u);
  const std::filesystem::path root = TRAINSIM_SOURCE_DIR;
  const std::regex fragment(R"(\b([a-z_]+)((\.[A-Za-z_][A-Za-z0-9_]*|\[[^\]]*\])+))");
  const std::set<std::string> file_extensions = {"csv",  "txt", "json", "png", "bin", "label",
                                                 "yaml", "md",  "sh",   "hpp", "cpp"};
  std::vector<std::string> problems;
  int files = 0;
  for (const char* dir : {"modules", "app"}) {
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root / dir)) {
      const std::string ext = entry.path().extension().string();
      if (ext != ".cpp" && ext != ".hpp")
        continue;
      ++files;
      std::ifstream in(entry.path());
      std::stringstream text;
      text << in.rdbuf();
      const std::string rel = entry.path().lexically_relative(root).generic_string();
      // The modules that read the scenario, and the apps on top of them.
      const bool reads_scenario = rel.starts_with("modules/sim/") ||
                                  rel.starts_with("modules/scenario/") || rel.starts_with("app/");
      const bool studio = rel.starts_with("app/studio/");
      for (const Literal& l : literals(text.str(), !studio)) {
        const std::string& lit = l.text;
        // A JSON path spelled out where the scenario is read: it must come from a binding.
        if (reads_scenario && lit.find('.') != std::string::npos &&
            declared.paths.count(withoutIndices(lit)) != 0)
          problems.push_back(rel + ": spells the scenario path \"" + lit + "\"");
        // A key read by string: x.at("key"), x["key"], x.get<T>("key"), setValue("key"), ….
        if (reads_scenario && l.read && declared.keys.count(lit) != 0)
          problems.push_back(rel + ": reads the scenario key \"" + lit + "\" by string");
        // A path named in a message or description must exist.
        for (std::sregex_iterator m(lit.begin(), lit.end(), fragment), end; m != end; ++m) {
          const std::string section = (*m)[1];
          if (declared.sections.count(section) == 0)
            continue;
          std::string path = withoutIndices(m->str());
          const std::string last = path.substr(path.rfind('.') + 1);
          if (file_extensions.count(last) != 0)
            continue;  // a file name such as trajectory.csv
          if (declared.paths.count(path) == 0)
            problems.push_back(rel + ": names \"" + path + "\", which is not a scenario path");
        }
      }
    }
  }
  ASSERT_GT(files, 50);
  for (const std::string& p : problems)
    ADD_FAILURE() << p;
}

}  // namespace
}  // namespace trainsim::sim

namespace trainsim::sim {
namespace {

// Every number has a physically meaningful range with both ends, so no value a user can type
// (1e308 for a noise density) reaches the physics; every array a maximum item count.
void collectUnbounded(const scenario::Param& p, const std::string& path,
                      std::vector<std::string>& out) {
  switch (p.type) {
    case scenario::ParamType::kNumber:
    case scenario::ParamType::kInteger:
      if (!p.minimum || !p.maximum || !std::isfinite(*p.minimum) || !std::isfinite(*p.maximum))
        out.push_back(path);
      break;
    case scenario::ParamType::kObject:
      for (const scenario::Param& f : p.fields)
        collectUnbounded(f, path.empty() ? f.key : path + "." + f.key, out);
      break;
    case scenario::ParamType::kArray:
      if (!p.max_items)
        out.push_back(path + " (item count)");
      collectUnbounded(*p.item, path + "[]", out);
      break;
    default:
      break;
  }
}

TEST(ScenarioRanges, EveryNumberHasAMinimumAndAMaximumAndEveryArrayAMaximumSize) {
  std::vector<std::string> unbounded;
  collectUnbounded(scenarioSchema().root(), "", unbounded);
  EXPECT_TRUE(unbounded.empty()) << ::testing::PrintToString(unbounded);
}

}  // namespace
}  // namespace trainsim::sim
