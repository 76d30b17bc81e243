// Every setting of a model declared once (issue 43): a model's table names each setting of its
// network and training run — its attribute in the model file's /config, its command-line option
// (--name with '-' for '_'), its help, its allowed values, whether a resumed run must keep it —
// and names the field that holds it by a member pointer of the network's struct C or the training
// run's T. A table is bound to the objects it describes when used: `bind(table, c, t)` to a
// tool's options or a model being read, `view(table, c, t)` to a const model written or compared
// (no copies). The command line (add_settings, called by the tool), the model file's save and
// load (write_settings, read_settings), the range checks (check_ranges) and the resume check
// (require_same_settings) all walk that table, so a new setting is one row (plus its schema line,
// which a unit test compares with the table).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "core/choice.h"
#include "io/h5.h"

namespace CLI {
class App;
class Option_group;
}  // namespace CLI

namespace df::models {

/// The values a numeric setting may take: an interval, either end open or closed or absent.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  bool holds(double v) const;
  /// As a message says it: "positive", "at least 2", "not negative", "in (0, 1]".
  std::string text() const;
};
/// > 0
inline Range positive() {
  return {.lo = 0, .lo_open = true};
}
/// >= lo
inline Range at_least(double lo) {
  return {.lo = lo};
}
/// An interval; the ends open where said.
inline Range within(double lo, double hi, bool lo_open = false, bool hi_open = false) {
  return {.lo = lo, .hi = hi, .lo_open = lo_open, .hi_open = hi_open};
}

/// A model's settings bound to the objects that hold them (bind / view below): a field's address,
/// or for an enum its text form. `Const`: bound for reading only (a const model is written or
/// compared through it, never copied first).
template <bool Const>
struct BasicSetting {
  template <class V>
  using Ptr = std::conditional_t<Const, const V*, V*>;
  /// A setting held in another type than text (an enum): how it reads and writes as text; `set`
  /// throws UsageError for a name it does not know (empty when bound for reading).
  struct Text {
    std::function<std::string()> get;
    std::function<void(const std::string&)> set = {};
    std::vector<std::string> names = {};  ///< the values it takes (an enum's, see choice())
  };
  using Target =
      std::variant<Ptr<bool>, Ptr<int>, Ptr<std::int64_t>, Ptr<std::uint64_t>, Ptr<double>,
                   Ptr<std::string>, Ptr<std::vector<int>>, Ptr<std::vector<double>>, Text>;
  const char* name = "";
  Target target;
  const char* help = "";
  std::vector<std::string> choices = {};
  const char* option = "";
  std::optional<Range> range = std::nullopt;
  bool resume = true;
  bool optional = false;
  /// The command line's name of it: `option`, or --name with '-' for '_'.
  std::string option_name() const;
  /// Its current value as the command line and messages write it ("10,5", "0.001", "true").
  std::string value_text() const;
};
/// Bound to objects it may set (the command line, reading a file, --paper-form's form).
using Setting = BasicSetting<false>;
using Settings = std::vector<Setting>;
/// Bound to objects it only reads (writing a file, the range and resume checks).
using SettingView = BasicSetting<true>;
using SettingViews = std::vector<SettingView>;

/// An enum field as a setting (see choice()).
template <class Owner, class E>
struct ChoiceField {
  E Owner::*field;
};
/// The target of an enum setting (core/choice.h): read and written by its names, which are also
/// the command line's choices. `choice(&MsaeConfig::support)`.
template <class Owner, class E>
ChoiceField<Owner, E> choice(E Owner::*field) {
  return {field};
}

/// One row of a model's table: a setting of its network (a field of C) or its training run (a
/// field of T), named once, with a member pointer to its field — bound to a model or to a tool's
/// options when used (bind, view).
template <class C, class T>
struct SettingRow {
  /// Of an object pair `c` and `t`, the one that holds a field of Owner.
  template <class Owner, class CC, class TT>
  static auto& holder(CC& c, TT& t) {
    if constexpr (std::is_same_v<Owner, C>)
      return c;
    else {
      static_assert(std::is_same_v<Owner, T>, "a setting's field belongs to C or T");
      return t;
    }
  }
  struct Text {
    std::function<std::string(const C&, const T&)> get;
    std::function<void(C&, T&, const std::string&)> set;
    std::vector<std::string> names;
    template <class Owner, class E>
    Text(ChoiceField<Owner, E> e)  // NOLINT: a row's `.target = choice(...)`
        : get([f = e.field](const C& c, const T& t) {
            return std::string(name_of(holder<Owner>(c, t).*f));
          }),
          set([f = e.field](C& c, T& t, const std::string& v) {
            holder<Owner>(c, t).*f = parse_choice<E>(v, "the value");
          }),
          names(choice_names<E>()) {}
  };
  template <class... O>
  using Fields = std::variant<bool O::*..., int O::*..., std::int64_t O::*...,
                              std::uint64_t O::*..., double O::*..., std::string O::*...,
                              std::vector<int> O::*..., std::vector<double> O::*..., Text>;
  using Target = Fields<C, T>;
  const char* name = "";  ///< the attribute in /config (snake_case)
  Target target;          ///< the field holding it
  /// The option's help; empty: not on the command line (set otherwise, e.g. the seed by --seed)
  const char* help = "";
  /// A string's allowed values on the command line (empty: any; for a choice(), its names)
  std::vector<std::string> choices = {};
  /// The option when it is not --name. A bool is a flag: --name sets it ("--separate"), a named
  /// option clears it ("--no-kl" for kl, "--freeze-decoder" for train_decoder)
  const char* option = "";
  /// A number's (each number's of a list) allowed values; none: any
  std::optional<Range> range = std::nullopt;
  /// A resumed run must have the same value (false: e.g. the iteration count it runs to)
  bool resume = true;
  /// Files written before the setting existed lack it and read as the field's current value (the
  /// default that reproduces them); false: a file without it is refused
  bool optional = false;

  /// This row bound to `c` and `t` (const objects: for reading).
  template <class CC, class TT>
  auto bound(CC& c, TT& t) const {
    constexpr bool read_only = std::is_const_v<CC>;
    using Out = BasicSetting<read_only>;
    Out s{.name = name,
          .target = {},
          .help = help,
          .choices = choices,
          .option = option,
          .range = range,
          .resume = resume,
          .optional = optional};
    s.target = std::visit(
        [&](const auto& field) -> typename Out::Target {
          if constexpr (std::is_same_v<std::decay_t<decltype(field)>, Text>) {
            typename Out::Text text{.get = [&c, &t, get = field.get] { return get(c, t); },
                                    .names = field.names};
            if constexpr (!read_only)
              text.set = [&c, &t, set = field.set](const std::string& v) { set(c, t, v); };
            return text;
          } else {
            return &(member_of(field, c, t));
          }
        },
        target);
    return s;
  }

 private:
  template <class V, class Owner, class CC, class TT>
  static auto& member_of(V Owner::*field, CC& c, TT& t) {
    return holder<Owner>(c, t).*field;
  }
};

/// A model's settings: its rows in /config's order. Built once (see msae_settings()), bound when
/// used.
template <class C, class T>
using SettingsTable = std::vector<SettingRow<C, T>>;

/// The table bound to objects it may set: the options of a tool, a model being read.
template <class C, class T>
Settings bind(const SettingsTable<C, T>& table, C& c, T& t) {
  Settings out;
  out.reserve(table.size());
  for (const auto& row : table) out.push_back(row.bound(c, t));
  return out;
}
/// The table bound to objects it reads: a model being written or compared, options checked.
template <class C, class T>
SettingViews view(const SettingsTable<C, T>& table, const C& c, const T& t) {
  SettingViews out;
  out.reserve(table.size());
  for (const auto& row : table) out.push_back(row.bound(c, t));
  return out;
}
/// Two tables of one model as one (e.g. the network's and the training run's).
template <class C, class T>
SettingsTable<C, T> joined(SettingsTable<C, T> a, const SettingsTable<C, T>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

/// Declares the settings that have help text as options of `group` (defaults shown; choices
/// checked; lists comma-separated; bools as flags, see Setting::option).
void add_settings(CLI::Option_group& group, const Settings& settings);

/// Refuses (UsageError: "--lr must be positive (got 0)") the first setting whose value lies
/// outside its range: the option checks every trainer shares; what is left in a trainer's own
/// check is the rules between settings.
void check_ranges(const SettingViews& settings);

/// Writes every setting as an attribute of `object` (bool and integers as integers, the 64-bit
/// seed as text, lists of numbers as number arrays).
void write_settings(h5::File& f, const std::string& object, const SettingViews& settings);

/// Reads every setting from `object`'s attributes into its field; an optional one that is absent
/// keeps the field's value, a required one that is absent is an InvalidInput naming the file.
void read_settings(const h5::File& f, const std::string& object, const Settings& settings);

/// Refuses (InvalidInput naming `path`) to resume a checkpoint whose `resume` settings differ from
/// this run's: the two tables must be the same model's, row by row.
void require_same_settings(const SettingViews& checkpoint, const SettingViews& now,
                           const std::string& path);

/// A form of the settings (e.g. a paper's exact one, `from`: a table of the same model) taken over
/// into `to` for every option the command line did not give (`given(option_name)`); settings that
/// are not options (no help, e.g. the seed) keep their values.
void take_settings_not_given(const SettingViews& from, const Settings& to,
                             const std::function<bool(const std::string&)>& given);
/// The same for the options `app` was not given (a tool's --paper-form).
void take_settings_not_given(const SettingViews& from, const Settings& to, const CLI::App& app);

}  // namespace df::models
