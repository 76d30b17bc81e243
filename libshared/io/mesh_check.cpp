#include "io/mesh_check.h"

#include <fmt/format.h>

#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <vector>

#include "core/error.h"

namespace df::io {
namespace {

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IOError("cannot read file", path);
  return {std::istreambuf_iterator<char>(in), {}};
}

// What std::istream >> (the readers' tokenizer) treats as white space.
bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v' || c == '\n';
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    std::size_t j = i;
    while (j < line.size() && !is_space(line[j])) ++j;
    if (j > i) tokens.push_back(line.substr(i, j - i));
    i = j;
  }
  return tokens;
}

bool parse_int(std::string_view s, std::int64_t& v) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

bool is_number(std::string_view s) {
  double v = 0;
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

/// Lines of a text body with their 1-based numbers.
class Lines {
 public:
  Lines(const std::string& text, std::size_t from = 0, std::size_t first_line = 1)
      : text_(text), pos_(from), number_(first_line - 1) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string::npos) end = text_.size();
    line = std::string_view(text_).substr(pos_, end - pos_);
    pos_ = end + 1;
    ++number_;
    return true;
  }
  std::size_t number() const { return number_; }

 private:
  const std::string& text_;
  std::size_t pos_, number_;
};

// --- OBJ

void check_obj(const std::string& path, const std::string& text) {
  std::int64_t counts[3] = {0, 0, 0};  // v, vt, vn defined so far
  const char* kinds[3] = {"vertex", "texture coordinate", "normal"};
  Lines lines(text);
  for (std::string_view line; lines.next(line);) {
    auto tokens = split(line);
    if (tokens.empty()) continue;
    const std::string where = path + ":" + std::to_string(lines.number());
    if (tokens[0] == "v") ++counts[0];
    if (tokens[0] == "vt") ++counts[1];
    if (tokens[0] == "vn") ++counts[2];
    if (tokens[0] != "f") continue;
    if (tokens.size() < 4) throw InvalidInput("face with fewer than 3 corners", where);
    for (std::size_t c = 1; c < tokens.size(); ++c) {
      std::string_view corner = tokens[c];
      for (int k = 0; k < 3 && !corner.empty(); ++k) {  // v[/vt[/vn]]
        std::size_t slash = corner.find('/');
        std::string_view part = corner.substr(0, slash);
        corner = slash == std::string_view::npos ? std::string_view() : corner.substr(slash + 1);
        if (part.empty() && k > 0) continue;  // "1//3"
        std::int64_t index = 0;
        if (!parse_int(part, index) || index == 0 || index > counts[k] || index < -counts[k])
          throw InvalidInput(
              fmt::format("face corner '{}' names {} {}, but {} are defined before it", tokens[c],
                          kinds[k], part, counts[k]),
              where);
      }
    }
  }
}

// --- OFF

void check_off(const std::string& path, const std::string& text) {
  Lines lines(text);
  std::string_view line;
  auto next_content = [&](std::vector<std::string_view>& tokens) {
    while (lines.next(line)) {
      tokens = split(line.substr(0, line.find('#')));
      if (!tokens.empty()) return true;
    }
    return false;
  };
  // OpenMesh reads OFF as a stream of tokens: a line with one token too many shifts every record
  // after it (a 'face' of 61 million corners, found by fuzzing). So the layout is checked
  // exactly, for plain OFF: x y z per vertex line, n and n indices per face line, no comments
  // in the body; the variants with colours, normals or texture coordinates are refused.
  auto next_body = [&](std::vector<std::string_view>& tokens) {
    while (lines.next(line)) {
      tokens = split(line);
      if (!tokens.empty()) return true;
    }
    return false;
  };
  std::vector<std::string_view> tokens;
  if (!next_content(tokens) || !tokens[0].ends_with("OFF"))
    throw InvalidInput("not an OFF file (no OFF keyword)", path);
  if (tokens[0] != "OFF")
    throw InvalidInput(
        fmt::format("only plain OFF is read (x y z per vertex line), not {}", tokens[0]), path);
  const bool binary = tokens.size() == 2 && tokens[1] == "BINARY";
  if (tokens.size() != (binary ? 2u : 1u))
    throw InvalidInput("the OFF keyword (or OFF BINARY) stands alone on its line", path);
  if (!binary)  // OpenMesh tokenizes differently around control bytes (a vertical tab: 20 GB)
    for (char c : text)
      if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r')
        throw InvalidInput(fmt::format("control character 0x{:02x} in a text OFF file", c), path);
  if (!next_content(tokens)) throw InvalidInput("OFF header without counts", path);
  const std::size_t first = 0;
  std::int64_t nv = -1, nf = -1;
  std::int64_t ne = 0;
  if (tokens.size() < first + 2 || tokens.size() > first + 3 || !parse_int(tokens[first], nv) ||
      !parse_int(tokens[first + 1], nf) || nv < 0 || nf < 0 ||
      (tokens.size() == first + 3 && !parse_int(tokens[first + 2], ne)))
    throw InvalidInput("OFF header needs vertex and face counts",
                       path + ":" + std::to_string(lines.number()));
  // the least a record takes: ASCII "0 0 0\n" and "3 0 1 2\n", binary 3 floats and 4 ints
  const auto size = static_cast<std::int64_t>(text.size());
  if (nv > size || nf > size || nv * (binary ? 12 : 6) + nf * (binary ? 16 : 8) > size)
    throw InvalidInput(
        fmt::format(
            "OFF header promises {} vertices and {} faces, more than the file's {} bytes hold", nv,
            nf, size),
        path);
  if (binary) return;
  for (std::int64_t v = 0; v < nv; ++v) {
    if (!next_body(tokens))
      throw InvalidInput(fmt::format("file ends after {} of {} vertices", v, nv), path);
    if (tokens.size() != 3 || !is_number(tokens[0]) || !is_number(tokens[1]) ||
        !is_number(tokens[2]))
      throw InvalidInput("a vertex line needs exactly 3 coordinates",
                         path + ":" + std::to_string(lines.number()));
  }
  for (std::int64_t f = 0; f < nf; ++f) {
    if (!next_body(tokens))
      throw InvalidInput(fmt::format("file ends after {} of {} faces", f, nf), path);
    const std::string where = path + ":" + std::to_string(lines.number());
    std::int64_t n = 0;
    if (!parse_int(tokens[0], n) || n < 3 || n + 1 != static_cast<std::int64_t>(tokens.size()))
      throw InvalidInput("a face line needs a corner count n >= 3 and exactly n vertex indices",
                         where);
    for (std::int64_t k = 1; k <= n; ++k) {
      std::int64_t index = 0;
      if (!parse_int(tokens[k], index) || index < 0 || index >= nv)
        throw InvalidInput(
            fmt::format("face corner '{}' is not a vertex index below {}", tokens[k], nv), where);
    }
  }
}

// --- PLY

struct PlyProperty {
  int size = 0;        // bytes of the value (binary)
  int count_size = 0;  // lists: bytes of the count, else 0
  bool is_int_count = true;
};
struct PlyElement {
  std::string name;
  std::int64_t count = 0;
  std::vector<PlyProperty> properties;
};

int ply_type_size(std::string_view t) {
  static const std::map<std::string_view, int> sizes = {
      {"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
      {"int16", 2}, {"uint16", 2},  {"int", 4},    {"uint", 4},   {"int32", 4}, {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  auto it = sizes.find(t);
  return it == sizes.end() ? 0 : it->second;
}

std::int64_t read_count(const std::string& text, std::size_t pos, int size, bool big_endian) {
  std::uint64_t v = 0;
  for (int i = 0; i < size; ++i) {
    auto byte = static_cast<unsigned char>(
        text[pos + static_cast<std::size_t>(big_endian ? i : size - 1 - i)]);
    v = (v << 8) | byte;
  }
  if (size < 8 && (v >> (8 * size - 1)) & 1) v |= ~std::uint64_t(0) << (8 * size);  // sign-extend
  return static_cast<std::int64_t>(v);
}

void check_ply(const std::string& path, const std::string& text) {
  Lines lines(text);
  std::string_view line;
  std::string format;
  std::vector<PlyElement> elements;
  if (!lines.next(line) || split(line) != std::vector<std::string_view>{"ply"})
    throw InvalidInput("not a PLY file (no 'ply' line)", path);
  bool ended = false;
  while (!ended && lines.next(line)) {
    auto t = split(line);
    const std::string where = path + ":" + std::to_string(lines.number());
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "format") {
      if (!format.empty() || t.size() != 3 ||
          (t[1] != "ascii" && t[1] != "binary_little_endian" && t[1] != "binary_big_endian") ||
          t[2] != "1.0")
        throw InvalidInput(
            "PLY needs one 'format ascii|binary_little_endian|binary_big_endian 1.0' line", where);
      format = t[1];
    } else if (t[0] == "element") {
      PlyElement e;
      if (t.size() != 3 || !parse_int(t[2], e.count) || e.count < 0)
        throw InvalidInput("PLY element line needs a name and a count", where);
      e.name = t[1];
      elements.push_back(e);
    } else if (t[0] == "property") {
      if (elements.empty()) throw InvalidInput("PLY property before any element", where);
      PlyProperty p;
      if (t.size() == 5 && t[1] == "list") {
        p.count_size = ply_type_size(t[2]);
        p.size = ply_type_size(t[3]);
        p.is_int_count = t[2].find("float") == std::string_view::npos && t[2] != "double";
        if (!p.count_size || !p.size || !p.is_int_count)
          throw InvalidInput("PLY list property with unknown or non-integer types", where);
      } else if (t.size() == 3) {
        p.size = ply_type_size(t[1]);
        if (!p.size)
          throw InvalidInput(fmt::format("PLY property of unknown type '{}'", t[1]), where);
      } else {
        throw InvalidInput("malformed PLY property line", where);
      }
      elements.back().properties.push_back(p);
    } else if (t[0] == "end_header") {
      ended = true;
    } else {
      throw InvalidInput(fmt::format("unknown PLY header line '{}'", t[0]), where);
    }
  }
  if (!ended) throw InvalidInput("PLY header without end_header", path);
  // OpenMesh's header parser loops forever when a token does not parse (a NUL byte, a form
  // feed inside a name, a version other than 1.0): the header must be plain text
  const std::size_t header_size = text.find("end_header");
  for (std::size_t i = 0; i < header_size; ++i) {
    auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 && c != '\t' && c != '\n' && c != '\r')
      throw InvalidInput(fmt::format("PLY header with control character 0x{:02x}", c), path);
  }
  if (format.empty()) throw InvalidInput("PLY header without a format line", path);
  for (const auto& e : elements)
    if (e.count > 0 && e.properties.empty())
      throw InvalidInput(fmt::format("PLY element '{}' has no properties", e.name), path);

  if (format == "ascii") {
    for (const auto& e : elements)
      for (std::int64_t r = 0; r < e.count; ++r) {
        std::vector<std::string_view> t;
        do {
          if (!lines.next(line))
            throw InvalidInput(
                fmt::format("file ends after {} of {} '{}' records", r, e.count, e.name), path);
          t = split(line);
        } while (t.empty());
        const std::string where = path + ":" + std::to_string(lines.number());
        std::size_t k = 0;
        for (const auto& p : e.properties) {
          std::int64_t n = 1;
          if (p.count_size) {
            if (k >= t.size() || !parse_int(t[k], n) || n < 0)
              throw InvalidInput("PLY list without a count", where);
            ++k;
          }
          if (n > static_cast<std::int64_t>(t.size() - k))
            throw InvalidInput(
                fmt::format("PLY '{}' record has fewer values than its properties call for",
                            e.name),
                where);
          for (std::int64_t i = 0; i < n; ++i, ++k)
            if (!is_number(t[k]))
              throw InvalidInput(fmt::format("'{}' is not a number", t[k]), where);
        }
        if (k != t.size())
          throw InvalidInput(
              fmt::format("PLY '{}' record has more values than its properties call for", e.name),
              where);
      }
    return;
  }
  // binary: walk every record within the file
  const bool big = format == "binary_big_endian";
  std::size_t header_end = text.find("end_header");
  std::size_t pos = text.find('\n', header_end) + 1;
  for (const auto& e : elements)
    for (std::int64_t r = 0; r < e.count; ++r)
      for (const auto& p : e.properties) {
        std::int64_t n = 1;
        if (p.count_size) {
          if (pos + static_cast<std::size_t>(p.count_size) > text.size())
            throw InvalidInput(
                fmt::format("file ends inside '{}' record {} of {}", e.name, r, e.count), path);
          n = read_count(text, pos, p.count_size, big);
          pos += static_cast<std::size_t>(p.count_size);
          if (n < 0)
            throw InvalidInput(fmt::format("'{}' record {} has a negative list count", e.name, r),
                               path);
        }
        if (n > static_cast<std::int64_t>((text.size() - pos) / static_cast<std::size_t>(p.size)))
          throw InvalidInput(
              fmt::format("file ends inside '{}' record {} of {}", e.name, r, e.count), path);
        pos += static_cast<std::size_t>(n) * static_cast<std::size_t>(p.size);
      }
}

}  // namespace

void check_mesh_structure(const std::string& path, const std::string& ext) {
  const std::string text = read_all(path);
  if (ext == ".obj") check_obj(path, text);
  if (ext == ".off") check_off(path, text);
  if (ext == ".ply") check_ply(path, text);
}

}  // namespace df::io
