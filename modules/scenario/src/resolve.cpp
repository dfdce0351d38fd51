// Validation and default-filling of scenario documents against the declared schema.

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "text.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/scenario/scenario.hpp"
#include "trainsim/scenario/schema.hpp"

namespace trainsim::scenario {

std::string Problem::text() const {
  return path.empty() ? message : path + ": " + message;
}

void Schema::add(Param section) {
  if (root_.field(section.key) != nullptr) {
    throw RuntimeError("scenario schema: section '" + section.key + "' is declared twice");
  }
  root_.fields.push_back(std::move(section));
}

void Schema::addCheck(ConsistencyCheck check) {
  checks_.push_back(std::move(check));
}

namespace {

std::string join(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string unitSuffix(const Param& p) {
  return p.unit.empty() ? "" : " " + p.unit;
}

class Resolver {
 public:
  explicit Resolver(std::vector<Problem>& problems) : problems_(problems) {}

  Json resolve(const Param& p, const Json* input, const std::string& path) {
    switch (p.type) {
      case ParamType::kObject:
        return resolveObject(p, input, path);
      case ParamType::kArray:
        return resolveArray(p, input, path);
      default:
        return resolveLeaf(p, input, path);
    }
  }

  /// Integer parameters declared with multipleOf(), with their resolved values.
  struct PendingMultiple {
    std::string path;
    const Param* param;
    std::int64_t value;
  };
  const std::vector<PendingMultiple>& pendingMultiples() const { return multiples_; }

 private:
  void problem(const std::string& path, std::string message) {
    problems_.push_back({path, std::move(message)});
  }

  Json resolveObject(const Param& p, const Json* input, const std::string& path) {
    static const Json kEmpty = Json::object();
    if (input != nullptr && !input->is_object()) {
      problem(path, fmt::format("expected an object, got {}", detail::describeValue(*input)));
      input = nullptr;
    }
    const Json& in = input != nullptr ? *input : kEmpty;
    std::vector<std::string> keys;
    keys.reserve(p.fields.size());
    for (const auto& f : p.fields)
      keys.push_back(f.key);
    for (const auto& [key, value] : in.items()) {
      if (p.field(key) != nullptr)
        continue;
      const std::string hint = detail::closestMatch(key, keys);
      problem(join(path, key.empty() ? std::string("\"\"") : messageValue(key)),
              hint.empty() ? std::string("unknown key")
                           : fmt::format("unknown key; did you mean '{}'?", hint));
    }
    Json out = Json::object();
    for (const auto& f : p.fields) {
      const auto it = in.find(f.key);
      out[f.key] = resolve(f, it != in.end() ? &*it : nullptr, join(path, f.key));
    }
    return out;
  }

  Json resolveArray(const Param& p, const Json* input, const std::string& path) {
    if (input != nullptr && !input->is_array()) {
      problem(path, fmt::format("expected an array, got {}", detail::describeValue(*input)));
      input = nullptr;
    }
    const Json& in = input != nullptr ? *input : p.default_value;
    if (p.max_items && in.size() > *p.max_items) {
      problem(path, fmt::format("has {} items; at most {} are allowed", in.size(), *p.max_items));
    }
    Json out = Json::array();
    const std::size_t outer_item = item_;
    for (std::size_t i = 0; i < in.size(); ++i) {
      item_ = i;
      out.push_back(resolve(*p.item, &in[i], fmt::format("{}[{}]", path, i)));
    }
    item_ = outer_item;
    return out;
  }

  Json resolveLeaf(const Param& p, const Json* input, const std::string& path) {
    if (input == nullptr) {
      recordMultiple(p, p.default_value, path);
      if (p.numbered_per_item && item_ > 0)
        return Json(fmt::format("{}_{}", p.default_value.get<std::string>(), item_));
      return p.default_value;
    }
    const Json& v = *input;
    auto wrongType = [&](const char* expected) {
      problem(path,
              fmt::format("expected {}{}, got {}", expected,
                          p.unit.empty() ? "" : " (" + p.unit + ")", detail::describeValue(v)));
      return p.default_value;
    };
    switch (p.type) {
      case ParamType::kBool:
        return v.is_boolean() ? v : wrongType("true or false");
      case ParamType::kString:
        return v.is_string() ? v : wrongType("a string");
      case ParamType::kEnum: {
        if (!v.is_string())
          return wrongType("a string");
        const auto& s = v.get_ref<const std::string&>();
        for (const auto& c : p.choices) {
          if (c == s)
            return v;
        }
        const std::string hint = detail::closestMatch(s, p.choices);
        problem(path,
                fmt::format("'{}' is not one of {}{}", messageValue(s), fmt::join(p.choices, ", "),
                            hint.empty() ? "" : fmt::format("; did you mean '{}'?", hint)));
        return p.default_value;
      }
      case ParamType::kInteger: {
        Json value;
        if (v.is_number_integer()) {
          if (v.is_number_unsigned() &&
              v.get<std::uint64_t>() >
                  static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
            problem(path, fmt::format("{} does not fit in a 64-bit integer", v.dump()));
            return p.default_value;
          }
          value = v.get<std::int64_t>();
        } else if (v.is_number_float() && std::trunc(v.get<double>()) == v.get<double>() &&
                   std::abs(v.get<double>()) < 9.2e18) {
          value = static_cast<std::int64_t>(v.get<double>());  // 1e7 written for 10000000
        } else {
          return wrongType("an integer");
        }
        if (!checkRange(p, static_cast<double>(value.get<std::int64_t>()), value.dump(), path)) {
          return p.default_value;
        }
        recordMultiple(p, value, path);
        return value;
      }
      case ParamType::kNumber: {
        if (!v.is_number())
          return wrongType("a number");
        const double d = v.get<double>();
        if (!checkRange(p, d, detail::formatNumber(d), path))
          return p.default_value;
        return Json(d);
      }
      case ParamType::kObject:
      case ParamType::kArray:
        break;
    }
    return p.default_value;
  }

  bool checkRange(const Param& p, double value, const std::string& text, const std::string& path) {
    if (p.minimum && value < *p.minimum) {
      problem(path, fmt::format("{}{} is below the minimum {}{}", text, unitSuffix(p),
                                detail::formatNumber(*p.minimum), unitSuffix(p)));
      return false;
    }
    if (p.maximum && value > *p.maximum) {
      problem(path, fmt::format("{}{} is above the maximum {}{}", text, unitSuffix(p),
                                detail::formatNumber(*p.maximum), unitSuffix(p)));
      return false;
    }
    return true;
  }

  void recordMultiple(const Param& p, const Json& value, const std::string& path) {
    if (!p.multiple_of.empty() && value.is_number_integer()) {
      multiples_.push_back({path, &p, value.get<std::int64_t>()});
    }
  }

  std::vector<Problem>& problems_;
  std::vector<PendingMultiple> multiples_;
  std::size_t item_ = 0;  // index of the array item being resolved (innermost)
};

}  // namespace

Schema::Resolution Schema::resolve(const Json& input) const {
  Resolution r;
  Resolver resolver(r.problems);
  r.resolved = resolver.resolve(root_, &input, "");
  if (!input.is_object()) {
    return r;  // the one problem already says the document is not an object
  }
  for (const auto& m : resolver.pendingMultiples()) {
    const Json* base = nullptr;
    try {
      base = &r.resolved.at(pointerFromPath(m.param->multiple_of));
    } catch (const std::exception&) {
      throw RuntimeError("scenario schema: " + m.path + " refers to undeclared " +
                         m.param->multiple_of);
    }
    const auto b = base->get<std::int64_t>();
    if (b <= 0 || m.value <= 0 || m.value % b != 0) {
      r.problems.push_back(
          {m.path, fmt::format("{} {} is not a positive multiple of {} ({} {})", m.value,
                               m.param->unit, m.param->multiple_of, b, m.param->unit)});
    }
  }
  if (r.problems.empty()) {
    for (const auto& check : checks_)
      check(r.resolved, r.problems);
  }
  // A hostile document can hold a hundred thousand bad keys; nobody reads past the first few.
  constexpr std::size_t kMaxProblems = 50;
  if (r.problems.size() > kMaxProblems) {
    const std::size_t more = r.problems.size() - kMaxProblems;
    r.problems.resize(kMaxProblems);
    r.problems.push_back({"", fmt::format("... and {} more problems", more)});
  }
  return r;
}

Json Schema::defaults() const {
  Resolution r = resolve(Json::object());
  if (!r.problems.empty()) {
    throw RuntimeError("scenario schema: the defaults are invalid: " + r.problems.front().text());
  }
  return r.resolved;
}

}  // namespace trainsim::scenario
