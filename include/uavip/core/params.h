#pragma once
/// \file
/// Parameter tables (PDAL's `ProgramArgs::add(name, description, variable, default)` is
/// the model). Each Options struct that a config file sets has one table beside it:
/// every key once, with its field (a member pointer or an accessor), its unit, a line
/// of help, its simple bounds and the layers that may set it besides the file. The
/// default is the field's initialiser, read from a default-constructed Options.
///
/// Who reads a table: the stage's `validate()` (the bounds, so options built in code
/// are refused like a bad file), the app layer's YAML reader (the keys it accepts, the
/// unknown-key check, which layer set each key, `auto`), and `uavip config --list`
/// (the scenario reference). Nothing here knows YAML. Header-only.
///
/// Precedence (the `layers` column): a value comes from the lowest to the highest of
/// default < aircraft profile < `auto` < file; a layer sets a key only when the key's
/// row allows it (`Layer`) and no higher layer has set it (`Sources::set`).

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/core/types.h"

namespace uavip::params {

/// Where a value came from, lowest precedence first.
enum class Source : std::uint8_t { Default, Profile, Auto, File };

/// "default", "profile", "auto", "file".
inline const char* sourceName(Source s) {
  switch (s) {
    case Source::Profile:
      return "profile";
    case Source::Auto:
      return "auto";
    case Source::File:
      return "file";
    default:
      return "default";
  }
}

/// The layers besides default and file that may set a key (bits).
enum Layer : unsigned { kFileOnly = 0U, kProfile = 1U, kAuto = 2U };

/// Which layer set each key ("section.key"); a key not listed has its default.
class Sources {
 public:
  /// Records that `source` set `key`, unless a higher layer already has; returns
  /// whether it did (the caller then writes the value).
  bool set(const std::string& key, Source source) {
    Source& s = by_key_[key];
    if (source < s) return false;
    s = source;
    return true;
  }
  /// The layer that set `key` (Default when none did).
  Source of(const std::string& key) const {
    const auto it = by_key_.find(key);
    return it == by_key_.end() ? Source::Default : it->second;
  }
  /// True when the file set `key`.
  bool fromFile(const std::string& key) const { return of(key) == Source::File; }
  /// True when the file set any key starting with `prefix` ("camera.").
  bool anyFromFile(const std::string& prefix) const {
    for (auto it = by_key_.lower_bound(prefix); it != by_key_.end(); ++it) {
      if (it->first.compare(0, prefix.size(), prefix) != 0) break;
      if (it->second == Source::File) return true;
    }
    return false;
  }

 private:
  std::map<std::string, Source> by_key_;
};

/// How a key is written in a file.
enum class Kind : std::uint8_t { Boolean, Integer, Number, Text, Numbers };

/// A key's value, kind-neutral: numbers (a boolean is 0/1, an integer is whole), or text;
/// `present` is false for an optional field left empty.
struct Value {
  std::vector<double> numbers;
  std::string text;
  bool present{true};
  double number() const { return numbers.empty() ? 0.0 : numbers.front(); }
};

/// Field ↔ Value conversions of the field types tables use.
inline Value toValue(double v) { return {{v}, {}, true}; }
inline Value toValue(int v) { return {{static_cast<double>(v)}, {}, true}; }
inline Value toValue(std::uint32_t v) { return {{static_cast<double>(v)}, {}, true}; }
inline Value toValue(std::size_t v) { return {{static_cast<double>(v)}, {}, true}; }
inline Value toValue(bool v) { return {{v ? 1.0 : 0.0}, {}, true}; }
inline Value toValue(const std::string& v) { return {{}, v, true}; }
inline Value toValue(const Vec3& v) { return {{v.x(), v.y(), v.z()}, {}, true}; }
inline Value toValue(const std::vector<int>& v) {
  Value out;
  for (const int i : v) out.numbers.push_back(static_cast<double>(i));
  return out;
}
template <typename T>
Value toValue(const std::optional<T>& v) {
  if (!v) return {{}, {}, false};
  return toValue(*v);
}

inline void fromValue(const Value& v, double& f) { f = v.number(); }
inline void fromValue(const Value& v, int& f) { f = static_cast<int>(v.number()); }
inline void fromValue(const Value& v, std::uint32_t& f) {
  f = static_cast<std::uint32_t>(v.number());
}
inline void fromValue(const Value& v, std::size_t& f) { f = static_cast<std::size_t>(v.number()); }
inline void fromValue(const Value& v, bool& f) { f = v.number() != 0.0; }
inline void fromValue(const Value& v, std::string& f) { f = v.text; }
inline void fromValue(const Value& v, Vec3& f) {
  for (int i = 0; i < 3; ++i) f[i] = v.numbers.at(static_cast<std::size_t>(i));
}
inline void fromValue(const Value& v, std::vector<int>& f) {
  f.clear();
  for (const double d : v.numbers) f.push_back(static_cast<int>(d));
}
template <typename T>
void fromValue(const Value& v, std::optional<T>& f) {
  if (!v.present) {
    f.reset();
    return;
  }
  T t{};
  fromValue(v, t);
  f = t;
}

/// The kind and count a field type is written with.
template <typename T>
struct KindOf {
  static constexpr Kind kind = std::is_same_v<T, double> ? Kind::Number : Kind::Integer;
  static constexpr std::size_t count = 1;
};
template <>
struct KindOf<bool> {
  static constexpr Kind kind = Kind::Boolean;
  static constexpr std::size_t count = 1;
};
template <>
struct KindOf<std::string> {
  static constexpr Kind kind = Kind::Text;
  static constexpr std::size_t count = 1;
};
template <>
struct KindOf<Vec3> {
  static constexpr Kind kind = Kind::Numbers;
  static constexpr std::size_t count = 3;
};
template <>
struct KindOf<std::vector<int>> {
  static constexpr Kind kind = Kind::Numbers;
  static constexpr std::size_t count = 1;  ///< set the row's count(lo, hi)
};
template <typename T>
struct KindOf<std::optional<T>> : KindOf<T> {};

/// One key of a table.
template <typename O>
struct Param {
  /// As written in the file; "section.key" once lifted into a section.
  std::string key;
  Kind kind{Kind::Number};
  std::string unit;            ///< "m", "m²", "deg", "s", "" for a count or a name
  std::string help;            ///< one line for the reference
  unsigned layers{kFileOnly};  ///< Layer bits: who may set it besides default and file
  double min{-std::numeric_limits<double>::infinity()};  ///< bound of every number
  double max{std::numeric_limits<double>::infinity()};
  bool min_open{false};      ///< min excluded
  bool max_open{false};      ///< max excluded
  std::size_t min_count{1};  ///< Numbers: how many
  std::size_t max_count{1};
  bool scalar_ok{false};             ///< Numbers: a single number stands for all
  bool whole{false};                 ///< Numbers: each must be a whole number
  std::vector<std::string> choices;  ///< Text: the values allowed (empty: any)
  std::function<Value(const O&)> get;
  std::function<void(O&, const Value&)> set;
  /// The field's address in `o`: finds the row of a field (Table::find).
  std::function<const void*(const O&)> address;

  // Builder steps, chained after Table::add.
  Param& unitIs(std::string u) {
    unit = std::move(u);
    return *this;
  }
  Param& positive() { return above(0.0); }
  Param& above(double m) {
    min = m;
    min_open = true;
    return *this;
  }
  Param& atLeast(double m) {
    min = m;
    min_open = false;
    return *this;
  }
  Param& atMost(double m) {
    max = m;
    max_open = false;
    return *this;
  }
  Param& below(double m) {
    max = m;
    max_open = true;
    return *this;
  }
  Param& within(double lo, double hi) { return atLeast(lo).atMost(hi); }
  Param& oneOf(std::vector<std::string> c) {
    choices = std::move(c);
    return *this;
  }
  Param& count(std::size_t lo, std::size_t hi) {
    min_count = lo;
    max_count = hi;
    return *this;
  }
  Param& orScalar() {
    scalar_ok = true;
    return *this;
  }
  /// Numbers: each a whole number (pixel counts, class codes).
  Param& integral() {
    whole = true;
    return *this;
  }
  /// The address of the field a function row stores (its first field), so that
  /// Table::find and Config::keyOf find the row.
  Param& storedAt(std::function<const void*(const O&)> a) {
    address = std::move(a);
    return *this;
  }
  /// `auto` may set it (app/config.h: resolved from the measured cloud).
  Param& mayBeAuto() {
    layers |= kAuto;
    return *this;
  }
  /// An aircraft profile may set it.
  Param& fromProfile() {
    layers |= kProfile;
    return *this;
  }

  bool bounded() const { return std::isfinite(min) || std::isfinite(max); }
  /// The bounds as text: "> 0", ">= 3", "in [0, 1]", "in (0, 90)"; empty when unbounded.
  std::string range() const {
    const bool lo = std::isfinite(min);
    const bool hi = std::isfinite(max);
    if (lo && hi) {
      return std::string("in ") + (min_open ? "(" : "[") + formatNumber(min) + ", " +
             formatNumber(max) + (max_open ? ")" : "]");
    }
    if (lo) return std::string(min_open ? "> " : ">= ") + formatNumber(min);
    if (hi) return std::string(max_open ? "< " : "<= ") + formatNumber(max);
    return {};
  }
  /// Empty when `v` is allowed, else what is wrong ("must be > 0, got -1").
  std::string problem(const Value& v) const {
    if (!v.present) return {};
    if (kind == Kind::Text) {
      if (choices.empty()) return {};
      std::string list;
      for (const auto& c : choices) {
        if (c == v.text) return {};
        list += (list.empty() ? "" : ", ") + c;
      }
      return "must be one of " + list + ", got '" + v.text + "'";
    }
    for (const double d : v.numbers) {
      const bool ok = std::isfinite(d) &&
                      (!std::isfinite(min) || (min_open ? d > min : d >= min)) &&
                      (!std::isfinite(max) || (max_open ? d < max : d <= max));
      if (!ok) return "must be " + (bounded() ? range() : "finite") + ", got " + formatNumber(d);
      if (whole && d != std::floor(d)) return "must hold whole numbers, got " + formatNumber(d);
    }
    return {};
  }
};

/// The keys of one Options struct `O`, in the order the reference lists them.
template <typename O>
class Table {
 public:
  /// A key whose field is `o.*field`.
  template <typename T>
  Param<O>& add(const std::string& key, T O::*field, const std::string& help) {
    Param<O> p;
    p.key = key;
    p.kind = KindOf<T>::kind;
    p.min_count = p.max_count = KindOf<T>::count;
    p.help = help;
    p.get = [field](const O& o) { return toValue(o.*field); };
    p.set = [field](O& o, const Value& v) { fromValue(v, o.*field); };
    p.address = [field](const O& o) -> const void* { return &(o.*field); };
    rows_.push_back(std::move(p));
    return rows_.back();
  }
  /// A key read and written by functions (a pair of fields, a value with a conversion).
  Param<O>& add(const std::string& key, Kind kind, std::function<Value(const O&)> get,
                std::function<void(O&, const Value&)> set, const std::string& help) {
    Param<O> p;
    p.key = key;
    p.kind = kind;
    p.help = help;
    p.get = std::move(get);
    p.set = std::move(set);
    p.address = [](const O&) -> const void* { return nullptr; };
    rows_.push_back(std::move(p));
    return rows_.back();
  }
  /// Every key of `inner`, reached through `o.*member`, its key prefixed by `prefix`
  /// ("perception." for a section, empty for a struct inside a section).
  template <typename I>
  void include(const std::string& prefix, I O::*member, const Table<I>& inner) {
    for (const Param<I>& q : inner.rows()) {
      Param<O> p;
      p.key = prefix + q.key;
      p.kind = q.kind;
      p.unit = q.unit;
      p.help = q.help;
      p.layers = q.layers;
      p.min = q.min;
      p.max = q.max;
      p.min_open = q.min_open;
      p.max_open = q.max_open;
      p.min_count = q.min_count;
      p.max_count = q.max_count;
      p.scalar_ok = q.scalar_ok;
      p.whole = q.whole;
      p.choices = q.choices;
      p.get = [member, g = q.get](const O& o) { return g(o.*member); };
      p.set = [member, s = q.set](O& o, const Value& v) { s(o.*member, v); };
      p.address = [member, a = q.address](const O& o) { return a(o.*member); };
      rows_.push_back(std::move(p));
    }
  }

  const std::vector<Param<O>>& rows() const { return rows_; }

  /// The row whose field is at `field` inside `o` (nullptr when none).
  const Param<O>* find(const O& o, const void* field) const {
    for (const auto& p : rows_) {
      if (p.address(o) == field) return &p;
    }
    return nullptr;
  }

  /// Checks every bounded key of `o`: throws InputError "<where>: <key> must be …, got …".
  void check(const O& o, const std::string& where) const {
    for (const auto& p : rows_) {
      const std::string what = p.problem(p.get(o));
      if (!what.empty()) throw InputError(where + ": " + p.key + " " + what);
    }
  }

 private:
  std::vector<Param<O>> rows_;
};

}  // namespace uavip::params
