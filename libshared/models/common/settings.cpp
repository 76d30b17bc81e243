#include "models/common/settings.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>

#include "core/error.h"

namespace df::models {

namespace {

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

std::string number_list(const auto& v) {
  return fmt::format("{}", fmt::join(v, ","));
}

}  // namespace

template <bool Const>
std::string BasicSetting<Const>::option_name() const {
  if (*option) return option;
  std::string n = std::string("--") + name;
  std::replace(n.begin(), n.end(), '_', '-');
  return n;
}

template <bool Const>
std::string BasicSetting<Const>::value_text() const {
  return std::visit(
      Overloaded{[](Ptr<bool> p) { return std::string(*p ? "true" : "false"); },
                 [](Ptr<std::string> p) { return *p; }, [](const Text& t) { return t.get(); },
                 [](Ptr<std::vector<int>> p) { return number_list(*p); },
                 [](Ptr<std::vector<double>> p) { return number_list(*p); },
                 [](auto p) { return fmt::format("{}", *p); }},
      target);
}

template struct BasicSetting<false>;
template struct BasicSetting<true>;

bool Range::holds(double v) const {
  return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
}

std::string Range::text() const {
  const bool low = std::isfinite(lo), high = std::isfinite(hi);
  if (low && !high) {
    if (lo == 0) return lo_open ? "positive" : "not negative";
    return fmt::format("{} {}", lo_open ? "above" : "at least", lo);
  }
  if (!low && high) return fmt::format("{} {}", hi_open ? "below" : "at most", hi);
  if (!low && !high) return "a number";
  return fmt::format("in {}{}, {}{}", lo_open ? '(' : '[', lo, hi, hi_open ? ')' : ']');
}

void check_ranges(const SettingViews& settings) {
  for (const SettingView& s : settings) {
    if (!s.range) continue;
    auto check = [&](double v) {
      if (!s.range->holds(v))
        throw UsageError(fmt::format("{} must be {} (got {})", s.option_name(), s.range->text(),
                                     s.value_text()));
    };
    std::visit(Overloaded{[&](const int* p) { check(*p); },
                          [&](const std::int64_t* p) { check(double(*p)); },
                          [&](const double* p) { check(*p); },
                          [&](const std::vector<int>* p) {
                            for (int v : *p) check(v);
                          },
                          [&](const std::vector<double>* p) {
                            for (double v : *p) check(v);
                          },
                          [&](const auto&) {
                            throw Error(
                                fmt::format("internal: setting {} has a range but is not "
                                            "a number",
                                            s.name));
                          }},
               s.target);
  }
}

void add_settings(CLI::Option_group& group, const Settings& settings) {
  for (const Setting& s : settings) {
    if (!*s.help) continue;
    const std::string flag = s.option_name();
    // A number's range is part of its help: "Adam learning rate [positive]".
    const std::string help =
        s.range ? fmt::format("{} [{}]", s.help, s.range->text()) : std::string(s.help);
    std::visit(
        Overloaded{
            [&](bool* p) {
              const bool given = !*s.option;  // --name sets it, a named option clears it
              if (given && *p) {  // on by default: the flag says so, and --no-name clears it
                group.add_flag_callback(
                    flag, [p] { *p = true; }, std::string(s.help) + " (the default)");
                group.add_flag_callback(
                    "--no-" + flag.substr(2), [p] { *p = false; },
                    fmt::format("The opposite of {} (on by default)", flag));
                return;
              }
              group.add_flag_callback(
                  flag, [p, given] { *p = given; }, s.help);
            },
            [&](std::vector<int>* p) {
              group.add_option(flag, *p, help)
                  ->delimiter(',')
                  ->allow_extra_args(false)
                  ->default_str(number_list(*p));
            },
            [&](std::vector<double>* p) {
              group.add_option(flag, *p, help)
                  ->delimiter(',')
                  ->allow_extra_args(false)
                  ->default_str(number_list(*p));
            },
            [&](std::string* p) {
              auto* o = group.add_option(flag, *p, help)->default_val(*p);
              if (!s.choices.empty()) o->check(CLI::IsMember(s.choices));
            },
            [&](const Setting::Text& t) {
              auto* o =
                  group.add_option_function<std::string>(flag, t.set, help)->default_str(t.get());
              const std::vector<std::string>& allowed = s.choices.empty() ? t.names : s.choices;
              if (!allowed.empty()) o->check(CLI::IsMember(allowed));
            },
            [&](auto* p) { group.add_option(flag, *p, help)->default_val(*p); }},
        s.target);
  }
}

void write_settings(h5::File& f, const std::string& object, const SettingViews& settings) {
  for (const SettingView& s : settings)
    std::visit(Overloaded{[&](const bool* p) { f.set_attr(object, s.name, static_cast<int>(*p)); },
                          [&](const int* p) { f.set_attr(object, s.name, *p); },
                          [&](const std::int64_t* p) { f.set_attr(object, s.name, *p); },
                          [&](const std::uint64_t* p) {
                            f.set_attr(object, s.name, fmt::format("{}", *p));
                          },
                          [&](const double* p) { f.set_attr(object, s.name, *p); },
                          [&](const std::string* p) { f.set_attr(object, s.name, *p); },
                          [&](const SettingView::Text& t) { f.set_attr(object, s.name, t.get()); },
                          [&](const std::vector<int>* p) {
                            const std::vector<double> v(p->begin(), p->end());
                            f.set_attr(object, s.name, std::span<const double>(v));
                          },
                          [&](const std::vector<double>* p) {
                            f.set_attr(object, s.name, std::span<const double>(*p));
                          }},
               s.target);
}

void read_settings(const h5::File& f, const std::string& object, const Settings& settings) {
  for (const Setting& s : settings) {
    if (!f.has_attr(object, s.name)) {
      if (s.optional) continue;
      throw InvalidInput(fmt::format("lacks the setting {}", s.name), f.where(object));
    }
    std::visit(Overloaded{[&](bool* p) { *p = f.attr_int(object, s.name) != 0; },
                          [&](int* p) { *p = static_cast<int>(f.attr_int(object, s.name)); },
                          [&](std::int64_t* p) { *p = f.attr_int(object, s.name); },
                          [&](std::uint64_t* p) {
                            const std::string text = f.attr_string(object, s.name);
                            try {
                              std::size_t used = 0;
                              *p = std::stoull(text, &used);
                              if (used != text.size()) throw std::invalid_argument(text);
                            } catch (const std::exception&) {
                              throw InvalidInput(
                                  fmt::format("{} is not a whole number: '{}'", s.name, text),
                                  f.where(object));
                            }
                          },
                          [&](double* p) { *p = f.attr_double(object, s.name); },
                          [&](std::string* p) { *p = f.attr_string(object, s.name); },
                          [&](const Setting::Text& t) {
                            try {
                              t.set(f.attr_string(object, s.name));
                            } catch (const UsageError& e) {
                              throw InvalidInput(fmt::format("{}: {}", s.name, e.what()),
                                                 f.where(object));
                            }
                          },
                          [&](std::vector<int>* p) {
                            p->clear();
                            for (double v : f.attr_doubles(object, s.name))
                              p->push_back(static_cast<int>(v));
                          },
                          [&](std::vector<double>* p) { *p = f.attr_doubles(object, s.name); }},
               s.target);
  }
}

void require_same_settings(const SettingViews& checkpoint, const SettingViews& now,
                           const std::string& path) {
  if (checkpoint.size() != now.size())
    throw Error("internal: require_same_settings needs two tables of the same model");
  for (std::size_t k = 0; k < now.size(); ++k) {
    if (!now[k].resume) continue;
    const std::string a = checkpoint[k].value_text(), b = now[k].value_text();
    if (a == b) continue;
    if (const auto* p = std::get_if<const bool*>(&now[k].target)) {
      // Said as the flag: whether the checkpoint's run gave it.
      const bool flag_now = (**p) == !*now[k].option;
      throw InvalidInput(fmt::format("checkpoint was made {} {}, this run {}; remove it or use the "
                                     "same settings",
                                     flag_now ? "without" : "with", now[k].option_name(),
                                     flag_now ? "gives it" : "does not"),
                         path);
    }
    throw InvalidInput(
        fmt::format("checkpoint was made with {} {}, this run has {}; remove it or use the "
                    "same settings",
                    now[k].option_name(), a, b),
        path);
  }
}

void take_settings_not_given(const SettingViews& from, const Settings& to,
                             const std::function<bool(const std::string&)>& given) {
  if (from.size() != to.size())
    throw Error("internal: take_settings_not_given needs two tables of the same model");
  for (std::size_t k = 0; k < to.size(); ++k) {
    if (!*to[k].help || given(to[k].option_name())) continue;
    std::visit(Overloaded{[&](const Setting::Text& t) {
                            t.set(std::get<SettingView::Text>(from[k].target).get());
                          },
                          [&](auto* p) {
                            using Field = std::remove_pointer_t<decltype(p)>;
                            *p = *std::get<const Field*>(from[k].target);
                          }},
               to[k].target);
  }
}

void take_settings_not_given(const SettingViews& from, const Settings& to, const CLI::App& app) {
  take_settings_not_given(from, to,
                          [&](const std::string& option) { return app.count(option) > 0; });
}

}  // namespace df::models
