#include "core/error.h"

namespace df {

std::string Error::message() const {
  if (where_.empty()) return what();
  return std::string(what()) + " (" + where_ + ")";
}

}  // namespace df
