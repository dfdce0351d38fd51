// Bounded JSON parsing for every document a user hands TrainSim (scenarios, studio files).
//
// nlohmann's own DOM parser accepts any nesting depth (and everything that walks the result
// afterwards — dump, copy, comparison — recurses), keeps the last of duplicate keys silently
// and reports a number overflow as an out_of_range exception without a position. So the text
// goes through nlohmann's SAX parser (iterative, with a position on every error) into the small
// DOM builder below, which limits the depth, refuses duplicate keys naming both lines, and
// turns every parser error into one "<source>:<line>:<column>: ..." line. The builder is ours
// because nlohmann's json_sax_dom_parser lives in its detail namespace and cannot be told any
// of this.

#include <fmt/format.h>

#include <iterator>
#include <string>
#include <unordered_map>
#include <vector>

#include "trainsim/scenario/scenario.hpp"

namespace trainsim::scenario {
namespace {

struct TextPosition {
  std::size_t line = 1;
  std::size_t column = 1;
};

TextPosition positionOf(std::string_view text, std::size_t offset) {
  TextPosition p;
  offset = std::min(offset, text.size());
  for (std::size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') {
      ++p.line;
      p.column = 1;
    } else {
      ++p.column;
    }
  }
  return p;
}

// A char iterator that tells how far the parser has read, so that a SAX event knows where in
// the text it happened (nlohmann passes positions to parse errors only).
class CountingIterator {
 public:
  using iterator_category = std::forward_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  CountingIterator() = default;
  CountingIterator(const char* p, const char* begin, std::size_t* consumed)
      : p_(p), begin_(begin), consumed_(consumed) {}
  reference operator*() const { return *p_; }
  CountingIterator& operator++() {
    ++p_;
    if (consumed_ != nullptr)
      *consumed_ = static_cast<std::size_t>(p_ - begin_);
    return *this;
  }
  CountingIterator operator++(int) {
    CountingIterator old = *this;
    ++*this;
    return old;
  }
  bool operator==(const CountingIterator& o) const { return p_ == o.p_; }
  bool operator!=(const CountingIterator& o) const { return p_ != o.p_; }

 private:
  const char* p_ = nullptr;
  const char* begin_ = nullptr;
  std::size_t* consumed_ = nullptr;
};

class BoundedDomBuilder {
 public:
  using number_integer_t = Json::number_integer_t;
  using number_unsigned_t = Json::number_unsigned_t;
  using number_float_t = Json::number_float_t;
  using string_t = Json::string_t;
  using binary_t = Json::binary_t;

  BoundedDomBuilder(std::string_view text, std::string_view source, const std::size_t* consumed)
      : text_(text), source_(source), consumed_(consumed) {}

  Json take() { return std::move(root_); }

  bool null() { return put(Json(nullptr)); }
  bool boolean(bool v) { return put(Json(v)); }
  bool number_integer(number_integer_t v) { return put(Json(v)); }
  bool number_unsigned(number_unsigned_t v) { return put(Json(v)); }
  bool number_float(number_float_t v, const string_t& /*text*/) { return put(Json(v)); }
  bool string(string_t& v) { return put(Json(std::move(v))); }
  bool binary(binary_t& /*v*/) { fail("binary values are not JSON"); }

  bool start_object(std::size_t /*elements*/) {
    open(Json::object());
    keys_.emplace_back();
    return true;
  }
  bool key(string_t& k) {
    const std::size_t at = *consumed_;
    const auto [it, fresh] = keys_.back().emplace(k, at);
    if (!fresh) {
      throw ConfigError(fmt::format(
          "{}:{}: duplicate key \"{}\" (first at line {}): a key may appear once per object",
          source_, positionOf(text_, at).line, messageValue(k),
          positionOf(text_, it->second).line));
    }
    key_ = std::move(k);
    return true;
  }
  bool end_object() {
    keys_.pop_back();
    stack_.pop_back();
    return true;
  }
  bool start_array(std::size_t /*elements*/) {
    open(Json::array());
    return true;
  }
  bool end_array() {
    stack_.pop_back();
    return true;
  }

  bool parse_error(std::size_t position, const std::string& /*token*/,
                   const nlohmann::detail::exception& e) {
    // nlohmann reports the byte just past the offending character.
    const TextPosition p = positionOf(text_, position > 0 ? position - 1 : 0);
    std::string reason = e.what();
    if (const auto colon = reason.find("] "); colon != std::string::npos)
      reason = reason.substr(colon + 2);  // drop "[json.exception.parse_error.101]"
    if (const auto colon = reason.find(": ");
        reason.rfind("parse error", 0) == 0 && colon != std::string::npos)
      reason = reason.substr(colon + 2);  // drop "parse error at line 3, column 9"
    throw ConfigError(fmt::format("{}:{}:{}: malformed JSON: {}", source_, p.line, p.column,
                                  messageValue(reason, 160)));
  }

 private:
  [[noreturn]] void fail(std::string_view what) {
    const TextPosition p = positionOf(text_, *consumed_);
    throw ConfigError(fmt::format("{}:{}:{}: {}", source_, p.line, p.column, what));
  }

  Json* insert(Json value) {
    if (stack_.empty()) {
      root_ = std::move(value);
      return &root_;
    }
    Json& parent = *stack_.back();
    if (parent.is_object())
      return &(parent[key_] = std::move(value));
    parent.push_back(std::move(value));
    return &parent.back();
  }
  bool put(Json value) {
    insert(std::move(value));
    return true;
  }
  void open(Json container) {
    if (stack_.size() >= kMaxJsonDepth)
      fail(fmt::format("nesting deeper than {} levels", kMaxJsonDepth));
    // Only the innermost open container grows, so the pointers to the outer ones stay valid.
    stack_.push_back(insert(std::move(container)));
  }

  std::string_view text_;
  std::string_view source_;
  const std::size_t* consumed_;
  Json root_;
  std::vector<Json*> stack_;
  std::vector<std::unordered_map<std::string, std::size_t>> keys_;  // key -> offset, per object
  std::string key_;
};

}  // namespace

Json parseJson(std::string_view text, std::string_view source) {
  if (text.size() > kMaxInputBytes) {
    throw ConfigError(fmt::format("{}: {} bytes is more than the {} MiB an input may hold", source,
                                  text.size(), kMaxInputBytes >> 20));
  }
  std::size_t consumed = 0;
  BoundedDomBuilder builder(text, source, &consumed);
  const char* begin = text.data();
  Json::sax_parse(CountingIterator(begin, begin, &consumed),
                  CountingIterator(begin + text.size(), begin, nullptr), &builder);
  return builder.take();
}

}  // namespace trainsim::scenario
