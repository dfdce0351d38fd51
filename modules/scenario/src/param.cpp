#include "trainsim/scenario/param.hpp"

namespace trainsim::scenario {

const Param* Param::field(std::string_view field_key) const {
  for (const auto& f : fields) {
    if (f.key == field_key)
      return &f;
  }
  return nullptr;
}

namespace {
Param leaf(std::string key, ParamType type, Json default_value, std::string unit,
           std::string description) {
  Param p;
  p.key = std::move(key);
  p.type = type;
  p.default_value = std::move(default_value);
  p.unit = std::move(unit);
  p.description = std::move(description);
  return p;
}
}  // namespace

Param boolean(std::string key, bool default_value, std::string description) {
  return leaf(std::move(key), ParamType::kBool, default_value, "", std::move(description));
}

Param integer(std::string key, std::int64_t default_value, std::string unit,
              std::string description) {
  return leaf(std::move(key), ParamType::kInteger, default_value, std::move(unit),
              std::move(description));
}

Param number(std::string key, double default_value, std::string unit, std::string description) {
  return leaf(std::move(key), ParamType::kNumber, default_value, std::move(unit),
              std::move(description));
}

Param string(std::string key, std::string default_value, std::string description) {
  return leaf(std::move(key), ParamType::kString, std::move(default_value), "",
              std::move(description));
}

Param choice(std::string key, std::string default_value, std::vector<std::string> choices,
             std::string description) {
  Param p =
      leaf(std::move(key), ParamType::kEnum, std::move(default_value), "", std::move(description));
  p.choices = std::move(choices);
  return p;
}

Param object(std::string key, std::string description, std::vector<Param> fields) {
  Param p;
  p.key = std::move(key);
  p.type = ParamType::kObject;
  p.description = std::move(description);
  p.fields = std::move(fields);
  return p;
}

Param array(std::string key, std::string description, Param item, Json default_items) {
  Param p;
  p.key = std::move(key);
  p.type = ParamType::kArray;
  p.description = std::move(description);
  p.item = std::make_shared<const Param>(std::move(item));
  p.default_value = std::move(default_items);
  return p;
}

const char* typeName(ParamType type) {
  switch (type) {
    case ParamType::kBool:
      return "boolean";
    case ParamType::kInteger:
      return "integer";
    case ParamType::kNumber:
      return "number";
    case ParamType::kString:
      return "string";
    case ParamType::kEnum:
      return "enum";
    case ParamType::kObject:
      return "object";
    case ParamType::kArray:
      return "array";
  }
  return "?";
}

}  // namespace trainsim::scenario
