// Every setting of a model declared once (issue 43): a model's table names each setting of its
// network and training run — its attribute in the model file's /config, its command-line option
// (--name with '-' for '_'), its help, its allowed values, whether a resumed run must keep it —
// and points at the field that holds it. The command line (add_settings, called by the tool),
// the model file's save and load (write_settings, read_settings) and the resume check
// (require_same_settings) all walk that table, so a new setting is one row (plus its schema line,
// which a unit test compares with the table).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
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

struct Setting {
  /// A setting held in another type than text (an enum): how it reads and writes as text; `set`
  /// throws UsageError for a name it does not know.
  struct Text {
    std::function<std::string()> get;
    std::function<void(const std::string&)> set;
    std::vector<std::string> names = {};  ///< the values it takes (an enum's, see choice())
  };
  using Target = std::variant<bool*, int*, std::int64_t*, std::uint64_t*, double*, std::string*,
                              std::vector<int>*, std::vector<double>*, Text>;
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
  /// The command line's name of it: `option`, or --name with '-' for '_'.
  std::string option_name() const;
  /// Its current value as the command line and messages write it ("10,5", "0.001", "true").
  std::string value_text() const;
};
using Settings = std::vector<Setting>;

/// The target of an enum setting (core/choice.h): read and written by its names, which are also
/// the command line's choices.
template <class E>
Setting::Text choice(E& field) {
  return {[&field] { return std::string(name_of(field)); },
          [&field](const std::string& v) { field = parse_choice<E>(v, "the value"); },
          choice_names<E>()};
}

/// Declares the settings that have help text as options of `group` (defaults shown; choices
/// checked; lists comma-separated; bools as flags, see Setting::option).
void add_settings(CLI::Option_group& group, const Settings& settings);

/// Refuses (UsageError: "--lr must be positive (got 0)") the first setting whose value lies
/// outside its range: the option checks every trainer shares; what is left in a trainer's own
/// check is the rules between settings.
void check_ranges(const Settings& settings);

/// Writes every setting as an attribute of `object` (bool and integers as integers, the 64-bit
/// seed as text, lists of numbers as number arrays).
void write_settings(h5::File& f, const std::string& object, const Settings& settings);

/// Reads every setting from `object`'s attributes into its field; an optional one that is absent
/// keeps the field's value, a required one that is absent is an InvalidInput naming the file.
void read_settings(const h5::File& f, const std::string& object, const Settings& settings);

/// Refuses (InvalidInput naming `path`) to resume a checkpoint whose `resume` settings differ from
/// this run's: the two tables must be the same model's, row by row.
void require_same_settings(const Settings& checkpoint, const Settings& now,
                           const std::string& path);

/// A form of the settings (e.g. a paper's exact one, `from`: a table of the same model) taken over
/// into `to` for every option the command line did not give (`given(option_name)`); settings that
/// are not options (no help, e.g. the seed) keep their values.
void take_settings_not_given(const Settings& from, const Settings& to,
                             const std::function<bool(const std::string&)>& given);
/// The same for the options `app` was not given (a tool's --paper-form).
void take_settings_not_given(const Settings& from, const Settings& to, const CLI::App& app);

}  // namespace df::models
