// A named enum (core/choice.h) as a command-line option: its names are the choices and the
// default shown; `allowed` narrows them where a tool takes only some.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "core/choice.h"

namespace df {

template <NamedChoice E>
CLI::Option* add_choice(CLI::App& app, const std::string& flag, E& field, const std::string& help,
                        std::vector<std::string> allowed = {}) {
  if (allowed.empty()) allowed = choice_names<E>();
  return app
      .add_option_function<std::string>(
          flag, [&field](const std::string& v) { field = parse_choice<E>(v, "the value"); }, help)
      ->default_str(std::string(name_of(field)))
      ->check(CLI::IsMember(allowed));
}

}  // namespace df
