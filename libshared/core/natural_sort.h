// Natural ordering of file names: digit runs compare by value, so `2.obj` < `10.obj`.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace df {

/// true if a sorts before b in natural order (digit runs by value, then the rest bytewise).
bool natural_less(std::string_view a, std::string_view b);
void natural_sort(std::vector<std::string>& names);

}  // namespace df
