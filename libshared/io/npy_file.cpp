#include "io/npy_file.h"

#include <fmt/format.h>

#include <bit>
#include <cstring>
#include <limits>
#include <regex>

#include "core/error.h"
#include "io/file_bytes.h"

namespace df::io {
namespace {

// The header's dictionary, as numpy writes it: {'descr': '<f4', 'fortran_order': False,
// 'shape': (3, 4), } (keys in any order, spaces optional).
struct Header {
  std::string descr;
  bool fortran = false;
  std::vector<std::int64_t> shape;
};

Header parse_header(const std::string& h, const std::string& name) {
  Header r;
  std::smatch m;
  if (!std::regex_search(h, m, std::regex(R"('descr'\s*:\s*'([^']*)')")))
    throw InvalidInput("a .npy header without 'descr'", name);
  r.descr = m[1];
  if (!std::regex_search(h, m, std::regex(R"('fortran_order'\s*:\s*(True|False))")))
    throw InvalidInput("a .npy header without 'fortran_order'", name);
  r.fortran = m[1] == "True";
  if (!std::regex_search(h, m, std::regex(R"('shape'\s*:\s*\(([^)]*)\))")))
    throw InvalidInput("a .npy header without 'shape'", name);
  const std::string dims = m[1];
  const std::regex number(R"(\s*(\d+)\s*(,|$))");
  for (auto it = std::sregex_iterator(dims.begin(), dims.end(), number);
       it != std::sregex_iterator(); ++it)
    r.shape.push_back(std::stoll((*it)[1]));
  return r;
}

template <class T>
T load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

}  // namespace

NpyArray parse_npy(std::string_view bytes, const std::string& name) {
  static_assert(std::endian::native == std::endian::little, "a little-endian machine");
  if (bytes.size() < 10 || bytes.substr(0, 6) != "\x93NUMPY")
    throw InvalidInput("not a .npy array (no \\x93NUMPY magic)", name);
  const int major = static_cast<unsigned char>(bytes[6]);
  if (major < 1 || major > 3)
    throw InvalidInput(fmt::format(".npy format version {} is not known", major), name);
  const std::size_t length_size = major == 1 ? 2 : 4;
  if (bytes.size() < 8 + length_size) throw InvalidInput("a truncated .npy header", name);
  const std::size_t header_length =
      major == 1 ? load<std::uint16_t>(bytes.data() + 8) : load<std::uint32_t>(bytes.data() + 8);
  const std::size_t data_at = 8 + length_size + header_length;
  if (bytes.size() < data_at) throw InvalidInput("a truncated .npy header", name);
  const Header h = parse_header(std::string(bytes.substr(8 + length_size, header_length)), name);

  NpyArray a;
  a.shape = h.shape;
  a.dtype = h.descr;
  std::size_t count = 1;
  for (const auto d : h.shape) {
    if (d != 0 && count > std::numeric_limits<std::size_t>::max() / 8 / static_cast<std::size_t>(d))
      throw InvalidInput("a .npy shape too large to address", name);
    count *= static_cast<std::size_t>(d);
  }
  const char order = h.descr.empty() ? '?' : h.descr[0];
  const std::string kind = h.descr.size() > 1 ? h.descr.substr(1) : "";
  const bool little = order == '<' || order == '|' || order == '=';
  std::size_t width = 0;
  if (kind == "f4" || kind == "i4") width = 4;
  if (kind == "f8" || kind == "i8") width = 8;
  if (!little || width == 0)
    throw InvalidInput(fmt::format("a .npy array of dtype '{}': only little-endian float32, "
                                   "float64, int32 and int64 numbers are read",
                                   h.descr),
                       name);
  if (bytes.size() - data_at < count * width)
    throw InvalidInput(fmt::format("a truncated .npy array: {} bytes of data for {} elements of {}",
                                   bytes.size() - data_at, count, h.descr),
                       name);
  a.values.resize(count);
  const char* data = bytes.data() + data_at;
  auto convert = [&]<class T>(T) {  // the type chosen once, not per element
    for (std::size_t k = 0; k < count; ++k)
      a.values[k] = static_cast<double>(load<T>(data + k * sizeof(T)));
  };
  if (kind == "f4") convert(float{});
  if (kind == "f8") convert(double{});
  if (kind == "i4") convert(std::int32_t{});
  if (kind == "i8") convert(std::int64_t{});
  if (h.fortran && a.shape.size() > 1) {  // column-major: the first index runs fastest
    std::vector<double> c(count);
    std::vector<std::int64_t> index(a.shape.size(), 0);
    for (std::size_t k = 0; k < count; ++k) {  // k walks the Fortran order; index its subscripts
      std::size_t row_major = 0;
      for (std::size_t d = 0; d < index.size(); ++d)
        row_major =
            row_major * static_cast<std::size_t>(a.shape[d]) + static_cast<std::size_t>(index[d]);
      c[row_major] = a.values[k];
      for (std::size_t d = 0; d < index.size() && ++index[d] == a.shape[d]; ++d) index[d] = 0;
    }
    a.values = std::move(c);
  }
  return a;
}

NpyArray read_npy(const std::string& path) {
  return parse_npy(read_file_bytes(path), path);
}

}  // namespace df::io
