#include "core/natural_sort.h"

#include <algorithm>
#include <cctype>

namespace df {

bool natural_less(std::string_view a, std::string_view b) {
  std::size_t i = 0, j = 0;
  auto digit = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; };
  while (i < a.size() && j < b.size()) {
    if (digit(a[i]) && digit(b[j])) {
      std::size_t i0 = i, j0 = j;
      while (i0 < a.size() && a[i0] == '0') ++i0;  // skip leading zeros
      while (j0 < b.size() && b[j0] == '0') ++j0;
      std::size_t i1 = i0, j1 = j0;
      while (i1 < a.size() && digit(a[i1])) ++i1;
      while (j1 < b.size() && digit(b[j1])) ++j1;
      std::size_t la = i1 - i0, lb = j1 - j0;
      if (la != lb) return la < lb;
      int c = a.substr(i0, la).compare(b.substr(j0, lb));
      if (c != 0) return c < 0;
      // Same value: fewer leading zeros first, then continue.
      if ((i1 - i) != (j1 - j)) return (i1 - i) < (j1 - j);
      i = i1;
      j = j1;
    } else {
      if (a[i] != b[j]) return static_cast<unsigned char>(a[i]) < static_cast<unsigned char>(b[j]);
      ++i;
      ++j;
    }
  }
  return (a.size() - i) < (b.size() - j);
}

void natural_sort(std::vector<std::string>& names) {
  std::stable_sort(names.begin(), names.end(),
                   [](const std::string& a, const std::string& b) { return natural_less(a, b); });
}

}  // namespace df
