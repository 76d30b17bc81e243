// NumPy's .npy arrays (format versions 1-3), the form joint-position data sets are shared in
// (HumanAct12, NTU's processed skeletons, AMASS-derived joint sets): numbers of little-endian
// float32/float64/int32/int64 in C or Fortran order, read whole into doubles in C (row-major)
// order, and unicode strings ('<U n', a scalar or a list: class labels). Anything else
// (big-endian, objects, byte strings) is an InvalidInput naming the file.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace df::io {

struct NpyArray {
  std::vector<std::int64_t> shape;   ///< as stored ([] for a scalar)
  std::string dtype;                 ///< numpy's descr, e.g. "<f4"
  std::vector<double> values;        ///< every element, row-major (numbers)
  std::vector<std::string> strings;  ///< every element (a unicode dtype '<U n'), UTF-8
  bool is_text() const { return !dtype.empty() && dtype.size() > 1 && dtype[1] == 'U'; }
};

/// Reads a .npy file. IOError when it cannot be read, InvalidInput (naming `path`) when it is not
/// a .npy array of numbers.
NpyArray read_npy(const std::string& path);
/// The same from bytes already in memory (`name` names them in errors).
NpyArray parse_npy(std::string_view bytes, const std::string& name);

}  // namespace df::io
