#pragma once
// Options declared once. An options struct lists its fields in one table,
//
//   template <class Self, class Table> static void table(Self& self, Table& t) {
//     t.field("weight", self.weight, "Soft-constraint weight", Range::above(0));
//     t.group("flow", self.flow);  // a nested options struct: JSON object "flow", flags --flow-…
//   }
//
// and validation, JSON (the provenance written into outputs) and the command-line binding are
// generated from it, so a knob's field name, JSON key and flag are one word: field `dense_weight`
// ↔ key "dense_weight" ↔ --dense-weight (a group's name prefixes its flags: `crease.weight` ↔
// {"crease": {"weight"}} ↔ --crease-weight). Units are part of the name: _edges (template mean
// edge lengths), _height (fraction of the template's height), _mm, _deg, _px. A mode that can be
// switched off is a std::optional (off: null in JSON, "off" on the command line), not a sentinel.

#include <CLI/CLI.hpp>

#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "surfcap/core/error.hpp"
#include "surfcap/core/json_document.hpp"

namespace surfcap::core {

/// The admissible values of a numeric option: an interval, each end open or closed.
struct Range {
  double low = -std::numeric_limits<double>::infinity();
  double high = std::numeric_limits<double>::infinity();
  bool low_open = false, high_open = false;

  static Range any() { return {}; }
  static Range at_least(double low) { return {low, std::numeric_limits<double>::infinity(), false, false}; }
  static Range above(double low) { return {low, std::numeric_limits<double>::infinity(), true, false}; }
  static Range closed(double low, double high) { return {low, high, false, false}; }
  static Range above_to(double low, double high) { return {low, high, true, false}; }  ///< (low, high]
  static Range from_below(double low, double high) { return {low, high, false, true}; }  ///< [low, high)
  static Range open(double low, double high) { return {low, high, true, true}; }

  bool contains(double value) const {
    if (!std::isfinite(value)) return false;
    return (low_open ? value > low : value >= low) && (high_open ? value < high : value <= high);
  }
  std::string text() const {
    std::ostringstream out;
    if (std::isinf(high)) {
      if (std::isinf(low)) return "finite";
      out << (low_open ? "> " : "≥ ") << low;
    } else {
      out << "in " << (low_open ? "(" : "[") << low << ", " << high << (high_open ? ")" : "]");
    }
    return out.str();
  }
};

/// The flag of a table entry: "--" + prefix + name with '_' → '-'.
inline std::string option_flag(const std::string& prefix, const std::string& name) {
  std::string flag = "--" + prefix + name;
  for (char& c : flag)
    if (c == '_') c = '-';
  return flag;
}

namespace option_table_detail {

template <class T>
struct is_optional : std::false_type {};
template <class T>
struct is_optional<std::optional<T>> : std::true_type {};

/// Walks a table with a visitor `v(path_prefix, flag_prefix, name, field, help, range)`.
template <class Visit>
class Walker {
 public:
  Walker(Visit& visit, std::string json_path, std::string flag_prefix)
      : visit_(visit), path_(std::move(json_path)), prefix_(std::move(flag_prefix)) {}
  template <class T>
  void field(const char* name, T& value, const char* help, Range range = Range::any()) {
    visit_(path_, prefix_, std::string(name), value, help, range);
  }
  /// A nested options struct: JSON object `name`, flags prefixed "name-".
  template <class Group>
  void group(const char* name, Group& nested) {
    Walker sub(visit_, path_ + name + ".", prefix_ + name + "_");
    std::remove_const_t<Group>::table(nested, sub);
  }
  /// A nested options struct whose fields read as the parent's own (no JSON object, no prefix).
  template <class Group>
  void inline_group(Group& nested) {
    std::remove_const_t<Group>::table(nested, *this);
  }

 private:
  Visit& visit_;
  std::string path_;
  std::string prefix_;
};

template <class Options, class Visit>
void walk(Options& options, Visit&& visit) {
  Walker<std::remove_reference_t<Visit>> walker(visit, "", "");
  std::remove_const_t<Options>::table(options, walker);
}

inline Json& json_at(Json& root, const std::string& dotted_prefix) {
  Json* node = &root;
  std::size_t start = 0;
  for (std::size_t dot = dotted_prefix.find('.'); dot != std::string::npos; dot = dotted_prefix.find('.', start)) {
    node = &(*node)[dotted_prefix.substr(start, dot - start)];
    start = dot + 1;
  }
  return *node;
}

template <class T>
std::string value_text(const T& value) {
  if constexpr (is_optional<T>::value) {
    return value ? value_text(*value) : std::string("off");
  } else if constexpr (std::is_same_v<T, bool>) {
    return value ? "true" : "false";
  } else {
    std::ostringstream out;
    out << value;
    return out.str();
  }
}

}  // namespace option_table_detail

/// Throws bad_arguments naming the first field outside its range (its flag and its value).
template <class Options>
void validate_options(const Options& options) {
  option_table_detail::walk(options, [](const std::string&, const std::string& prefix, const std::string& name,
                                        const auto& value, const char*, const Range& range) {
    using T = std::decay_t<decltype(value)>;
    if constexpr (std::is_same_v<T, bool>) {
      return;
    } else {
      double number = 0;
      if constexpr (option_table_detail::is_optional<T>::value) {
        if (!value) return;
        number = static_cast<double>(*value);
      } else {
        number = static_cast<double>(value);
      }
      if (!range.contains(number))
        throw bad_arguments(option_flag(prefix, name) + " must be " + range.text() + " (got " +
                            option_table_detail::value_text(value) + ")");
    }
  });
}

/// Every field of the table as JSON (groups as nested objects; an option switched off is null).
template <class Options>
Json options_to_json(const Options& options) {
  Json json = Json::object();
  option_table_detail::walk(options, [&json](const std::string& path, const std::string&, const std::string& name,
                                             const auto& value, const char*, const Range&) {
    using T = std::decay_t<decltype(value)>;
    Json& object = option_table_detail::json_at(json, path);
    if constexpr (option_table_detail::is_optional<T>::value) {
      object[name] = value ? Json(*value) : Json(nullptr);
    } else {
      object[name] = value;
    }
  });
  return json;
}

/// The table's entries as dotted JSON paths ("crease.weight"), in table order.
template <class Options>
std::vector<std::string> option_paths(const Options& options) {
  std::vector<std::string> paths;
  option_table_detail::walk(options, [&paths](const std::string& path, const std::string&, const std::string& name,
                                              const auto&, const char*, const Range&) { paths.push_back(path + name); });
  return paths;
}

/// Binds every field of the table to `command`: numbers as --flag VALUE (optional ones also
/// accept "off"), booleans as --flag / --no-flag. Values are range-checked when parsed.
template <class Options>
void add_options(CLI::App* command, Options& options) {
  option_table_detail::walk(options, [command](const std::string&, const std::string& prefix, const std::string& name,
                                               auto& value, const char* help, const Range& range) {
    using T = std::decay_t<decltype(value)>;
    const std::string flag = option_flag(prefix, name);
    if constexpr (std::is_same_v<T, bool>) {
      command->add_flag(flag + ",!--no-" + flag.substr(2), value, help);
    } else if constexpr (option_table_detail::is_optional<T>::value) {
      using V = typename T::value_type;
      auto* option = command->add_option_function<std::string>(
          flag,
          [&value, flag, range](const std::string& text) {
            if (text == "off") {
              value.reset();
              return;
            }
            V parsed{};
            if (!CLI::detail::lexical_cast(text, parsed))
              throw CLI::ValidationError(flag, "expects a number or \"off\", got " + text);
            if (!range.contains(static_cast<double>(parsed)))
              throw CLI::ValidationError(flag, "must be " + range.text() + " (got " + text + ")");
            value = parsed;
          },
          std::string(help) + " (off: disabled)");
      option->default_str(option_table_detail::value_text(value))->type_name(std::is_integral_v<V> ? "INT|off" : "FLOAT|off");
    } else {
      auto* option = command->add_option(flag, value, help);
      option->check(CLI::Validator(
          [range, flag](std::string& text) -> std::string {
            double parsed = 0;
            if (!CLI::detail::lexical_cast(text, parsed)) return "expects a number, got " + text;
            return range.contains(parsed) ? std::string() : "must be " + range.text() + " (got " + text + ")";
          },
          range.text()));
    }
  });
}

}  // namespace surfcap::core
