// A mode as an enum with one list of its names (issue 69): the names its files and command line
// use, in the order --help shows them. Parsing, printing and the allowed values all read that
// list, so a new mode is one enumerator and one row.
//
// An enum takes part by a names_of overload that argument-dependent lookup finds beside it:
//
//   enum class Support { soft, proximal, hard };
//   inline constexpr Named<Support> kSupportNames[] = {
//       {"soft", Support::soft}, {"proximal", Support::proximal}, {"hard", Support::hard}};
//   constexpr std::span<const Named<Support>> names_of(Support) { return kSupportNames; }
#pragma once

#include <fmt/format.h>

#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/error.h"

namespace df {

template <class E>
struct Named {
  std::string_view name;
  E value;
};

/// The name of a mode (its enumerator's row).
template <class E>
std::string_view name_of(E value) {
  for (const Named<E>& n : names_of(E{}))
    if (n.value == value) return n.name;
  throw Error(fmt::format("internal: enumerator {} has no name", static_cast<int>(value)));
}

/// Every name of the enum, in the list's order.
template <class E>
std::vector<std::string> choice_names() {
  std::vector<std::string> out;
  for (const Named<E>& n : names_of(E{})) out.emplace_back(n.name);
  return out;
}

/// The mode called `text`; a UsageError naming `what` and every allowed name otherwise.
template <class E>
E parse_choice(std::string_view text, std::string_view what) {
  for (const Named<E>& n : names_of(E{}))
    if (n.name == text) return n.value;
  throw UsageError(fmt::format("{} must be one of {}, not '{}'", what,
                               fmt::join(choice_names<E>(), ", "), text));
}

/// An enum with a names_of list.
template <class E>
concept NamedChoice = std::is_enum_v<E> && requires(E e) {
  names_of(e);
};

}  // namespace df

/// fmt writes a named enum by its name.
template <df::NamedChoice E>
struct fmt::formatter<E> : fmt::formatter<std::string_view> {
  auto format(E value, format_context& ctx) const {
    return fmt::formatter<std::string_view>::format(df::name_of(value), ctx);
  }
};
