#include "io/npy_file.h"

#include <fmt/format.h>

#include <bit>
#include <charconv>
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

// One code point as UTF-8.
void append_utf8(std::string& out, std::uint32_t c) {
  if (c < 0x80) {
    out += static_cast<char>(c);
  } else if (c < 0x800) {
    out += static_cast<char>(0xC0 | (c >> 6));
    out += static_cast<char>(0x80 | (c & 0x3F));
  } else if (c < 0x10000) {
    out += static_cast<char>(0xE0 | (c >> 12));
    out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (c & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (c >> 18));
    out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (c & 0x3F));
  }
}

// numpy's unicode dtype '<U n': n UTF-32LE code units per element, NUL-padded; a scalar or a list.
void read_strings(NpyArray& a, const std::string& kind, std::size_t count, const Header& h,
                  std::string_view data, const std::string& name) {
  std::size_t chars = 0;
  const auto [stop, ec] = std::from_chars(kind.data() + 1, kind.data() + kind.size(), chars);
  if (ec != std::errc() || stop != kind.data() + kind.size() || chars == 0 || chars > 4096)
    throw InvalidInput(fmt::format("a .npy string dtype '{}' not understood", h.descr), name);
  if (h.shape.size() > 1)
    throw InvalidInput("a .npy array of strings with more than one dimension", name);
  if (data.size() / (4 * chars) < count)
    throw InvalidInput(fmt::format("a truncated .npy array: {} bytes of data for {} strings of {}",
                                   data.size(), count, h.descr),
                       name);
  for (std::size_t k = 0; k < count; ++k) {
    std::string text;
    for (std::size_t i = 0; i < chars; ++i) {
      const auto c = load<std::uint32_t>(data.data() + 4 * (k * chars + i));
      if (c == 0) break;
      if (c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF))
        throw InvalidInput(fmt::format("string {} has code point {:#x}, not unicode", k, c), name);
      append_utf8(text, c);
    }
    a.strings.push_back(std::move(text));
  }
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
  if (little && kind.size() > 1 && kind[0] == 'U') {  // labels: fixed-width UTF-32 strings
    read_strings(a, kind, count, h, bytes.substr(data_at), name);
    return a;
  }
  std::size_t width = 0;
  if (kind == "f4" || kind == "i4") width = 4;
  if (kind == "f8" || kind == "i8") width = 8;
  if (!little || width == 0)
    throw InvalidInput(fmt::format("a .npy array of dtype '{}': only little-endian float32, "
                                   "float64, int32 and int64 numbers (and unicode strings) are "
                                   "read",
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
