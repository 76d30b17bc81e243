#include "io/mesh_check.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "core/error.h"
#include "io/file_bytes.h"

namespace df::io {
namespace {

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

/// Lines of a text body with their 1-based numbers.
class Lines {
 public:
  explicit Lines(const std::string& text) : text_(text) {}
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
  /// "path:line" of the current line, for messages (built only when one is thrown).
  std::string where(const std::string& path) const { return path + ":" + std::to_string(number_); }

 private:
  const std::string& text_;
  std::size_t pos_ = 0, number_ = 0;
};

// A number as strtod reads it, nan and inf included.
bool parse_number(std::string_view s, double& v) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

/// Whether `s` is a number; a NaN/Inf is an InvalidInput at the current line (OpenMesh's OBJ
/// reader drops such a vertex, its OFF reader then reads garbage indices).
bool is_coordinate(std::string_view s, const Lines& lines, const std::string& path) {
  double v = 0;
  if (!parse_number(s, v)) return false;
  if (!std::isfinite(v))
    throw InvalidInput("non-finite coordinate (NaN or Inf)", lines.where(path));
  return true;
}

/// Text formats must not hold control characters in [begin, end): OpenMesh's tokenizer and
/// ours would split them differently (found by fuzzing: endless loops, a 20 GB allocation).
void refuse_control_characters(const std::string& text, std::size_t end, const std::string& what,
                               const std::string& path) {
  for (std::size_t i = 0; i < std::min(end, text.size()); ++i) {
    auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 && c != '\t' && c != '\n' && c != '\r')
      throw InvalidInput(fmt::format("control character 0x{:02x} in {}", c, what), path);
  }
}

// --- OBJ

MeshTextScan check_obj(const std::string& path, const std::string& text) {
  MeshTextScan scan;
  std::int64_t counts[3] = {0, 0, 0};  // v, vt, vn defined so far
  const char* kinds[3] = {"vertex", "texture coordinate", "normal"};
  Lines lines(text);
  for (std::string_view line; lines.next(line);) {
    auto tokens = split(line);
    if (tokens.empty()) continue;
    if (tokens[0] == "v") {
      ++counts[0];
      for (std::size_t k = 1; k < tokens.size(); ++k) is_coordinate(tokens[k], lines, path);
    }
    if (tokens[0] == "vt") ++counts[1];
    if (tokens[0] == "vn") ++counts[2];
    if (tokens[0] != "f") continue;
    ++scan.obj_face_lines;
    if (tokens.size() < 4) throw InvalidInput("face with fewer than 3 corners", lines.where(path));
    for (std::size_t c = 1; c < tokens.size(); ++c) {
      std::string_view corner = tokens[c];
      for (int k = 0; k < 3 && !corner.empty(); ++k) {  // v[/vt[/vn]]
        std::size_t slash = corner.find('/');
        std::string_view part = corner.substr(0, slash);
        corner = slash == std::string_view::npos ? std::string_view() : corner.substr(slash + 1);
        if (part.empty() && k > 0) continue;  // "1//3"
        std::int64_t index = 0;
        if (parse_int(part, index) && index == 0)
          throw InvalidInput(
              fmt::format("face corner '{}' names {} 0: OBJ counts from 1 (or back from -1)",
                          tokens[c], kinds[k]),
              lines.where(path));
        if (!parse_int(part, index) || index > counts[k] || index < -counts[k])
          throw InvalidInput(
              fmt::format("face corner '{}' names {} {}, but {} are defined before it", tokens[c],
                          kinds[k], part, counts[k]),
              lines.where(path));
      }
    }
  }
  scan.obj_vertex_lines = static_cast<std::size_t>(counts[0]);
  return scan;
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
  if (!binary) refuse_control_characters(text, text.size(), "a text OFF file", path);
  if (!next_content(tokens)) throw InvalidInput("OFF header without counts", path);
  std::int64_t nv = -1, nf = -1, ne = 0;
  if (tokens.size() < 2 || tokens.size() > 3 || !parse_int(tokens[0], nv) ||
      !parse_int(tokens[1], nf) || nv < 0 || nf < 0 ||
      (tokens.size() == 3 && !parse_int(tokens[2], ne)))
    throw InvalidInput("OFF header needs vertex and face counts", lines.where(path));
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
    if (tokens.size() != 3 || !is_coordinate(tokens[0], lines, path) ||
        !is_coordinate(tokens[1], lines, path) || !is_coordinate(tokens[2], lines, path))
      throw InvalidInput("a vertex line needs exactly 3 coordinates", lines.where(path));
  }
  for (std::int64_t f = 0; f < nf; ++f) {
    if (!next_body(tokens))
      throw InvalidInput(fmt::format("file ends after {} of {} faces", f, nf), path);
    std::int64_t n = 0;
    if (!parse_int(tokens[0], n) || n < 3 || n + 1 != static_cast<std::int64_t>(tokens.size()))
      throw InvalidInput("a face line needs a corner count n >= 3 and exactly n vertex indices",
                         lines.where(path));
    for (std::int64_t k = 1; k <= n; ++k) {
      std::int64_t index = 0;
      if (!parse_int(tokens[k], index) || index < 0 || index >= nv)
        throw InvalidInput(
            fmt::format("face corner '{}' is not a vertex index below {}", tokens[k], nv),
            lines.where(path));
    }
  }
}

// --- PLY

struct PlyProperty {
  int size = 0;        // bytes of the value (binary)
  int count_size = 0;  // lists: bytes of the count, else 0
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

struct PlyHeader {
  std::string format;
  std::vector<PlyElement> elements;
  std::size_t end = 0;  // where 'end_header' starts
};

// The header: its format, elements and properties, each line checked; where it ends.
PlyHeader read_ply_header(const std::string& path, const std::string& text, Lines& lines) {
  std::string_view line;
  PlyHeader h;
  auto& format = h.format;
  auto& elements = h.elements;
  if (!lines.next(line) || split(line) != std::vector<std::string_view>{"ply"})
    throw InvalidInput("not a PLY file (no 'ply' line)", path);
  bool ended = false;
  while (!ended && lines.next(line)) {
    auto t = split(line);
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "format") {
      if (!format.empty() || t.size() != 3 ||
          (t[1] != "ascii" && t[1] != "binary_little_endian" && t[1] != "binary_big_endian") ||
          t[2] != "1.0")
        throw InvalidInput(
            "PLY needs one 'format ascii|binary_little_endian|binary_big_endian 1.0' line",
            lines.where(path));
      format = t[1];
    } else if (t[0] == "element") {
      PlyElement e;
      if (t.size() != 3 || !parse_int(t[2], e.count) || e.count < 0)
        throw InvalidInput("PLY element line needs a name and a count", lines.where(path));
      e.name = t[1];
      elements.push_back(e);
    } else if (t[0] == "property") {
      if (elements.empty())
        throw InvalidInput("PLY property before any element", lines.where(path));
      PlyProperty p;
      if (t.size() == 5 && t[1] == "list") {
        p.count_size = ply_type_size(t[2]);
        p.size = ply_type_size(t[3]);
        const bool int_count = t[2].find("float") == std::string_view::npos && t[2] != "double";
        if (!p.count_size || !p.size || !int_count)
          throw InvalidInput("PLY list property with unknown or non-integer types",
                             lines.where(path));
      } else if (t.size() == 3) {
        p.size = ply_type_size(t[1]);
        if (!p.size)
          throw InvalidInput(fmt::format("PLY property of unknown type '{}'", t[1]),
                             lines.where(path));
      } else {
        throw InvalidInput("malformed PLY property line", lines.where(path));
      }
      elements.back().properties.push_back(p);
    } else if (t[0] == "end_header") {
      ended = true;
    } else {
      throw InvalidInput(fmt::format("unknown PLY header line '{}'", t[0]), lines.where(path));
    }
  }
  if (!ended) throw InvalidInput("PLY header without end_header", path);
  // OpenMesh's header parser loops forever when a token does not parse (a NUL byte, a form
  // feed inside a name, a version other than 1.0): the header must be plain text
  h.end = text.find("end_header");
  refuse_control_characters(text, h.end, "a PLY header", path);
  if (format.empty()) throw InvalidInput("PLY header without a format line", path);
  for (const auto& e : elements)
    if (e.count > 0 && e.properties.empty())
      throw InvalidInput(fmt::format("PLY element '{}' has no properties", e.name), path);
  return h;
}

// An ASCII body: every record has as many numbers as its properties call for.
void check_ply_ascii(const std::string& path, Lines& lines,
                     const std::vector<PlyElement>& elements) {
  std::string_view line;
  for (const auto& e : elements)
    for (std::int64_t r = 0; r < e.count; ++r) {
      std::vector<std::string_view> t;
      do {
        if (!lines.next(line))
          throw InvalidInput(
              fmt::format("file ends after {} of {} '{}' records", r, e.count, e.name), path);
        t = split(line);
      } while (t.empty());
      std::size_t k = 0;
      for (const auto& p : e.properties) {
        std::int64_t n = 1;
        if (p.count_size) {
          if (k >= t.size() || !parse_int(t[k], n) || n < 0)
            throw InvalidInput("PLY list without a count", lines.where(path));
          ++k;
        }
        if (n > static_cast<std::int64_t>(t.size() - k))
          throw InvalidInput(
              fmt::format("PLY '{}' record has fewer values than its properties call for", e.name),
              lines.where(path));
        for (std::int64_t i = 0; i < n; ++i, ++k)
          if (!is_coordinate(t[k], lines, path))
            throw InvalidInput(fmt::format("'{}' is not a number", t[k]), lines.where(path));
      }
      if (k != t.size())
        throw InvalidInput(
            fmt::format("PLY '{}' record has more values than its properties call for", e.name),
            lines.where(path));
    }
}

// A binary body: walk every record within the file.
void check_ply_binary(const std::string& path, const std::string& text, std::size_t header_end,
                      const std::vector<PlyElement>& elements, bool big) {
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

void check_ply(const std::string& path, const std::string& text) {
  Lines lines(text);
  const PlyHeader h = read_ply_header(path, text, lines);
  if (h.format == "ascii")
    check_ply_ascii(path, lines, h.elements);
  else
    check_ply_binary(path, text, h.end, h.elements, h.format == "binary_big_endian");
}

}  // namespace

MeshTextScan check_mesh_structure(const std::string& path, const std::string& ext) {
  const std::string text = read_file_bytes(path);
  if (ext == ".obj") return check_obj(path, text);
  if (ext == ".off") check_off(path, text);
  if (ext == ".ply") check_ply(path, text);
  return {};
}

}  // namespace df::io
