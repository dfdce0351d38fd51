#pragma once

// A binding ties a scenario section to the struct the code runs on: each field is declared
// once — key, unit and its conversion, range, description, target field — and the struct's
// own member initialisers are the one default. From a binding come the schema declaration
// (defaults converted to the JSON unit), the reader from resolved JSON to the struct, the
// writer back to JSON, the JSON path of a field, and checks across fields that name real
// paths. So no key is read again by string and no default is written twice.
//
//   Binding<track::MotionLimits> b;
//   b.number("max_accel_m_s2", &track::MotionLimits::accel_m_s2, units::kNone("m/s^2"),
//            "Largest acceleration").range(0.01, 5);
//   Param section = b.declare("train", "The train");
//   track::MotionLimits limits = b.read(resolved.at("train"));

#include <algorithm>
#include <cmath>
#include <concepts>
#include <deque>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "trainsim/core/enum_names.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/scenario/param.hpp"
#include "trainsim/scenario/schema.hpp"

namespace trainsim::scenario {

/// The unit a JSON number is written in and its conversion to the SI value of the field:
/// SI = json × factor, or json / factor when `divides` (km/h → m/s is / 3.6, as exact as the
/// hand-written conversions it replaces).
struct Unit {
  const char* name = "";
  double factor = 1.0;
  bool divides = false;

  double toSi(double json) const { return divides ? json / factor : json * factor; }
  double fromSi(double si) const { return divides ? si * factor : si / factor; }
};

namespace units {
/// An SI unit (or none): the value is stored as written.
constexpr Unit si(const char* name) {
  return Unit{name, 1.0, false};
}
inline constexpr Unit kNone = si("");
inline constexpr Unit kMillimetre{"mm", 1e-3, false};
inline constexpr Unit kMillimetrePerSecond{"mm/s", 1e-3, false};
inline constexpr Unit kMillimetrePerMetre{"mm/m", 1e-3, false};
inline constexpr Unit kKilometrePerHour{"km/h", 3.6, true};
inline constexpr Unit kPermille{"permille", 1e-3, false};
inline constexpr Unit kDegree{"deg", std::numbers::pi / 180.0, false};  // trainsim::kRadPerDeg
inline constexpr Unit kPpm{"ppm", 1e-6, false};
inline constexpr Unit kMilliradian{"mrad", 1e-3, false};
}  // namespace units

/// A JSON value that stands for a special field value ("-1 lets the rules choose", "0: no
/// saturation"), converted as is in both directions.
struct Sentinel {
  double json;
  double si;
};

/// A default converted to its JSON unit, rounded to 12 significant digits so that 160/3.6 m/s
/// reads back as 160 km/h.
double jsonDefault(double value_si, const Unit& unit);

template <typename T>
class Binding;

/// A field of a member struct, as a binding's target or a path: nested(&RouteConfig::options,
/// &track::RouteOptions::station_dwell_s) reaches config.options.station_dwell_s.
template <typename T, typename M, typename U>
struct Nested {
  M T::*outer;
  U M::*inner;
  U& operator()(T& t) const { return t.*outer.*inner; }
  const U& operator()(const T& t) const { return t.*outer.*inner; }
};
template <typename T, typename M, typename U>
constexpr Nested<T, M, U> nested(M T::*outer, U M::*inner) {
  return {outer, inner};
}

/// Names the fields of one bound value by their JSON paths, for checks: at(t.field) is
/// "<prefix>.<key>" (nested objects included), at.key(t.field) the path below the prefix.
template <typename T>
class FieldPaths {
 public:
  FieldPaths(const Binding<T>& binding, std::string prefix, const T& value)
      : binding_(binding), prefix_(std::move(prefix)), value_(value) {}
  template <typename V>
  std::string operator()(const V& field) const {
    return prefix_ + "." + key(field);
  }
  template <typename V>
  std::string key(const V& field) const {
    return binding_.pathOf(value_, &field);
  }
  /// The path of the checked object itself.
  const std::string& prefix() const { return prefix_; }

 private:
  const Binding<T>& binding_;
  std::string prefix_;
  const T& value_;
};

template <typename T>
class Binding {
  template <typename Ref>
  using Value = std::remove_cvref_t<std::invoke_result_t<Ref, T&>>;

 public:
  template <typename>
  friend class Binding;

  /// A check on the typed value; `at` gives the JSON paths of its fields.
  using Check = std::function<void(const T&, const FieldPaths<T>& at, std::vector<Problem>&)>;

  Binding() : defaults_{} {}
  /// `defaults` stands in for T's member initialisers where T has none (Eigen vectors,
  /// GeodeticPoint).
  explicit Binding(T defaults) : defaults_(std::move(defaults)) {}

  /// A number field (double) in `unit`; ranges are in the JSON unit. `ref` is a member pointer
  /// or a callable T& -> double&.
  template <typename Ref>
  Param& number(std::string key, Ref ref, Unit unit, std::string description,
                std::optional<Sentinel> sentinel = std::nullopt) {
    Field& f = add(scenario::number(std::move(key), 0.0, unit.name, std::move(description)), ref);
    f.fill = [ref, unit, sentinel](const T& t, Param& p) {
      const double v = get(ref, t);
      p.default_value = sentinel && same(v, sentinel->si) ? sentinel->json : jsonDefault(v, unit);
    };
    f.read = [ref, unit, sentinel, k = f.proto.key](const Json& j, T& t) {
      const double v = j.at(k).template get<double>();
      std::invoke(ref, t) = sentinel && v == sentinel->json ? sentinel->si : unit.toSi(v);
    };
    f.write = [ref, unit, sentinel, k = f.proto.key](const T& t, Json& j) {
      const double v = get(ref, t);
      j[k] = sentinel && same(v, sentinel->si) ? sentinel->json : unit.fromSi(v);
    };
    return f.proto;
  }

  /// An integer field (any integral type), stored as written.
  template <typename Ref>
  Param& integer(std::string key, Ref ref, const char* unit, std::string description) {
    using V = Value<Ref>;
    static_assert(std::is_integral_v<V>);
    Field& f = add(scenario::integer(std::move(key), 0, unit, std::move(description)), ref);
    f.fill = [ref](const T& t, Param& p) { p.default_value = get(ref, t); };
    f.read = [ref, k = f.proto.key](const Json& j, T& t) {
      std::invoke(ref, t) = j.at(k).template get<V>();
    };
    f.write = [ref, k = f.proto.key](const T& t, Json& j) { j[k] = get(ref, t); };
    return f.proto;
  }

  template <typename Ref>
  Param& boolean(std::string key, Ref ref, std::string description) {
    return plain(scenario::boolean(std::move(key), false, std::move(description)), ref);
  }

  template <typename Ref>
  Param& string(std::string key, Ref ref, std::string description) {
    return plain(scenario::string(std::move(key), "", std::move(description)), ref);
  }

  /// An enum field; its JSON names come from the enum's table (trainsim::enumNames), less
  /// `excluded` values that the scenario may not choose.
  template <typename Ref>
  Param& choice(std::string key, Ref ref, std::string description,
                std::vector<Value<Ref>> excluded = {}) {
    using E = Value<Ref>;
    std::vector<std::string> names;
    for (const EnumName<E>& n : enumNames(E{}))
      if (std::find(excluded.begin(), excluded.end(), n.value) == excluded.end())
        names.emplace_back(n.name);
    Field& f =
        add(scenario::choice(std::move(key), "", std::move(names), std::move(description)), ref);
    f.fill = [ref](const T& t, Param& p) { p.default_value = std::string(nameOf(get(ref, t))); };
    f.read = [ref, k = f.proto.key](const Json& j, T& t) {
      const std::string name = j.at(k).template get<std::string>();
      const std::optional<E> v = enumFromName<E>(name);
      if (!v)  // the schema lets only declared names through
        throw RuntimeError(k + ": unknown name \"" + name + "\" (schema/code mismatch)");
      std::invoke(ref, t) = *v;
    };
    f.write = [ref, k = f.proto.key](const T& t, Json& j) {
      j[k] = std::string(nameOf(get(ref, t)));
    };
    return f.proto;
  }

  /// A nested object bound by `child`; its defaults are this struct's value of the field.
  template <typename Ref>
  Param& object(std::string key, Ref ref, const Binding<Value<Ref>>& child,
                std::string description) {
    Field& f = add(scenario::object(std::move(key), std::move(description), {}), ref);
    f.fill = [ref, &child](const T& t, Param& p) { p.fields = child.fields(get(ref, t)); };
    f.read = [ref, &child, k = f.proto.key](const Json& j, T& t) {
      std::invoke(ref, t) = child.read(j.at(k), get(ref, t));
    };
    f.write = [ref, &child, k = f.proto.key](const T& t, Json& j) {
      j[k] = child.write(get(ref, t));
    };
    f.check = [ref, &child, k = f.proto.key](const T& t, const std::string& prefix,
                                             std::vector<Problem>& out) {
      child.problems(get(ref, t), prefix + "." + k, out);
    };
    f.find = [ref, &child](const T& t, const void* address) {
      return child.find(get(ref, t), address);
    };
    return f.proto;
  }

  /// An array field (std::vector<U>) whose items are bound by `item`; its default items are
  /// this struct's value of the field, and an item's omitted fields take `item`'s defaults.
  template <typename Ref>
  Param& array(std::string key, Ref ref, const Binding<typename Value<Ref>::value_type>& item,
               std::string item_description, std::string description) {
    Field& f = add(scenario::array(std::move(key), std::move(description),
                                   scenario::object("", std::move(item_description), {})),
                   ref);
    f.fill = [ref, &item](const T& t, Param& p) {
      Param items = *p.item;
      items.fields = item.fields(item.defaults());
      p.item = std::make_shared<const Param>(std::move(items));
      Json list = Json::array();
      for (const auto& v : get(ref, t))
        list.push_back(item.write(v));
      p.default_value = std::move(list);
    };
    f.read = [ref, &item, k = f.proto.key](const Json& j, T& t) {
      auto& out = std::invoke(ref, t);
      out.clear();
      for (const Json& v : j.at(k))
        out.push_back(item.read(v));
    };
    f.write = [ref, &item, k = f.proto.key](const T& t, Json& j) {
      Json list = Json::array();
      for (const auto& v : get(ref, t))
        list.push_back(item.write(v));
      j[k] = std::move(list);
    };
    f.check = [ref, &item, k = f.proto.key](const T& t, const std::string& prefix,
                                            std::vector<Problem>& out) {
      const auto& list = get(ref, t);
      for (std::size_t i = 0; i < list.size(); ++i)
        item.problems(list[i], prefix + "." + k + "[" + std::to_string(i) + "]", out);
    };
    return f.proto;
  }

  /// Embeds the fields of `child` flat in this object: for a member struct whose fields are
  /// not nested in JSON (the name, period and mount every sensor declares first).
  template <typename Ref>
  void embed(Ref ref, Binding<Value<Ref>> child) {
    using U = Value<Ref>;
    const auto shared = std::make_shared<const Binding<U>>(std::move(child));
    for (const typename Binding<U>::Field& cf : shared->fields_) {
      Field& f = fields_.emplace_back();
      f.proto = cf.proto;
      f.address = [ref, cf](const T& t) { return cf.address(get(ref, t)); };
      f.fill = [ref, cf](const T& t, Param& p) { cf.fill(get(ref, t), p); };
      f.read = [ref, cf](const Json& j, T& t) { cf.read(j, std::invoke(ref, t)); };
      f.write = [ref, cf](const T& t, Json& j) { cf.write(get(ref, t), j); };
      if (cf.find)
        f.find = [ref, cf](const T& t, const void* a) { return cf.find(get(ref, t), a); };
      if (cf.check)
        f.check = [ref, cf](const T& t, const std::string& prefix, std::vector<Problem>& out) {
          cf.check(get(ref, t), prefix, out);
        };
    }
    if (!shared->checks_.empty())
      check([ref, shared](const T& t, const FieldPaths<T>& at, std::vector<Problem>& out) {
        const FieldPaths<U> sub(*shared, at.prefix(), get(ref, t));
        for (const auto& c : shared->checks_)
          c(get(ref, t), sub, out);
      });
  }

  /// A check across fields of this struct, run on every resolved value.
  void check(Check c) { checks_.push_back(std::move(c)); }
  /// The field `low` must not exceed the field `high` (min/max pairs); member pointers.
  template <typename M>
  void notAbove(M T::*low, M T::*high) {
    check([low, high](const T& t, const FieldPaths<T>& at, std::vector<Problem>& out) {
      if (t.*low > t.*high)
        out.push_back({at(t.*low), "must not exceed " + at.key(t.*high)});
    });
  }

  const T& defaults() const { return defaults_; }

  /// The declared fields with defaults taken from `defaults`.
  std::vector<Param> fields(const T& defaults) const {
    std::vector<Param> out;
    for (const Field& f : fields_) {
      Param p = f.proto;
      f.fill(defaults, p);
      out.push_back(std::move(p));
    }
    return out;
  }
  /// This binding as an object parameter.
  Param declare(std::string key, std::string description) const {
    return scenario::object(std::move(key), std::move(description), fields(defaults_));
  }

  /// The struct from a resolved (validated) object, starting from `base` (the defaults).
  T read(const Json& j) const { return read(j, defaults_); }
  T read(const Json& j, T base) const {
    for (const Field& f : fields_)
      f.read(j, base);
    return base;
  }
  Json write(const T& t) const {
    Json j = Json::object();
    for (const Field& f : fields_)
      f.write(t, j);
    return j;
  }

  /// Problems of the checks of this binding and its nested bindings; `path` is this object's.
  void problems(const T& t, const std::string& path, std::vector<Problem>& out) const {
    for (const Field& f : fields_)
      if (f.check)
        f.check(t, path, out);
    const FieldPaths<T> at(*this, path, t);
    for (const Check& c : checks_)
      c(t, at, out);
  }

  /// The JSON path, below this object, of the field of `t` at `address` ("length_m",
  /// "auxiliary.probability"). Throws if no field is bound there (a programming error).
  std::string pathOf(const T& t, const void* address) const {
    if (std::optional<std::string> p = find(t, address))
      return *p;
    throw RuntimeError("scenario binding: a field asked for by address is not bound");
  }
  /// The path of the field `get` reaches (a member pointer, or a callable const T& -> field).
  template <typename Get>
  std::string pathTo(const Get& get) const {
    return pathOf(defaults_, &std::invoke(get, defaults_));
  }
  std::optional<std::string> find(const T& t, const void* address) const {
    for (const Field& f : fields_)  // leaves first: a nested object may start at a leaf's address
      if (f.address(t) == address)
        return f.proto.key;
    for (const Field& f : fields_)
      if (f.find)
        if (std::optional<std::string> p = f.find(t, address))
          return f.proto.key + "." + *p;
    return std::nullopt;
  }

 private:
  struct Field {
    Param proto;                                   // the declaration without its default
    std::function<const void*(const T&)> address;  // of the bound value within a T
    std::function<std::optional<std::string>(const T&, const void*)> find;  // nested objects
    std::function<void(const T&, Param&)> fill;
    std::function<void(const Json&, T&)> read;
    std::function<void(const T&, Json&)> write;
    std::function<void(const T&, const std::string&, std::vector<Problem>&)> check;
  };

  // Reads through `ref` without changing `t` (callables take T&, member pointers need no cast).
  template <typename Ref>
  static const Value<Ref>& get(const Ref& ref, const T& t) {
    return std::invoke(ref, const_cast<T&>(t));
  }
  static bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

  template <typename Ref>
  Field& add(Param proto, const Ref& ref) {
    Field& f = fields_.emplace_back();
    f.proto = std::move(proto);
    f.address = [ref](const T& t) -> const void* { return &get(ref, t); };
    return f;
  }

  template <typename Ref>
  Param& plain(Param proto, Ref ref) {
    Field& f = add(std::move(proto), ref);
    f.fill = [ref](const T& t, Param& p) { p.default_value = get(ref, t); };
    f.read = [ref, k = f.proto.key](const Json& j, T& t) {
      std::invoke(ref, t) = j.at(k).template get<Value<Ref>>();
    };
    f.write = [ref, k = f.proto.key](const T& t, Json& j) { j[k] = get(ref, t); };
    return f.proto;
  }

  T defaults_;
  std::deque<Field> fields_;  // a deque: the Param& returned for chaining stays valid
  std::vector<Check> checks_;
};

/// A top-level scenario section: its key and description and the binding of its struct.
template <typename T>
struct Section {
  std::string key;
  std::string description;
  Binding<T> binding;

  Param declare() const { return binding.declare(key, description); }
  /// The section of a resolved scenario.
  T read(const Json& resolved) const { return binding.read(resolved.at(key)); }
  /// Checks that also read other sections of the resolved scenario.
  std::vector<std::function<void(const T&, const Json& resolved, std::vector<Problem>&)>>
      cross_checks;

  /// The JSON path of a field of this section: path(&RouteConfig::source) is "route.source";
  /// a callable reaches nested fields, path([](const RouteConfig& c) -> auto& { return
  /// c.generator.length_m; }) is "route.generator.length_m".
  template <typename Get>
  std::string path(const Get& get) const {
    return key + "." + binding.pathTo(get);
  }
  /// Adds the section and its checks to a schema.
  void addTo(Schema& schema) const {
    schema.add(declare());
    schema.addCheck([this](const Json& resolved, std::vector<Problem>& problems) {
      const T value = read(resolved);
      binding.problems(value, key, problems);
      for (const auto& c : cross_checks)
        c(value, resolved, problems);
    });
  }
};

}  // namespace trainsim::scenario
