#include "io/md2.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstring>

#include "core/error.h"
#include "io/file_bytes.h"

namespace df::io {
namespace {

template <class T>
T get(const std::string& d, std::size_t offset, const std::string& path) {
  if (offset + sizeof(T) > d.size()) throw InvalidInput("truncated MD2 file", path);
  T v;
  std::memcpy(&v, d.data() + offset, sizeof(T));
  return v;
}

std::string stem_of(const std::string& frame_name) {
  std::size_t end = frame_name.size();
  while (end > 0 && std::isdigit(static_cast<unsigned char>(frame_name[end - 1]))) --end;
  return end ? frame_name.substr(0, end) : frame_name;
}

}  // namespace

bool is_md2_file(const std::string& path) {
  return lower_extension(path) == ".md2";
}

Md2Model read_md2(const std::string& path) {
  const std::string d = read_file_bytes(path);
  if (d.size() < 68 || std::memcmp(d.data(), "IDP2", 4) != 0)
    throw InvalidInput("not an MD2 file (no IDP2 signature)", path);
  std::int32_t h[17];
  std::memcpy(h, d.data(), sizeof h);
  const int version = h[1], frame_size = h[4], n_vertices = h[6], n_tris = h[8], n_frames = h[10];
  if (version != 8) throw InvalidInput(fmt::format("unsupported MD2 version {}", version), path);
  // 64-bit arithmetic: the header's counts and offsets are anyone's 32-bit numbers (fuzzing found
  // 4 * n_vertices overflowing int)
  if (n_vertices <= 0 || n_tris <= 0 || n_frames <= 0 ||
      frame_size < 40 + 4 * static_cast<std::int64_t>(n_vertices))
    throw InvalidInput("MD2 header has impossible counts", path);
  auto fits = [&](std::int32_t offset, std::int64_t count, std::int64_t item_size) {
    const auto size = static_cast<std::int64_t>(d.size());
    return offset >= 0 && offset <= size && count * item_size <= size - offset;
  };
  if (!fits(h[13], n_tris, 12) || !fits(h[14], n_frames, frame_size))
    throw InvalidInput("truncated MD2 file", path);
  const auto ofs_tris = static_cast<std::size_t>(h[13]),
             ofs_frames = static_cast<std::size_t>(h[14]);

  Md2Model m;
  m.faces.resize(n_tris, 3);
  for (int t = 0; t < n_tris; ++t) {
    std::size_t o = ofs_tris + 12u * static_cast<std::size_t>(t);
    int a = get<std::uint16_t>(d, o, path), b = get<std::uint16_t>(d, o + 2, path),
        c = get<std::uint16_t>(d, o + 4, path);
    if (a >= n_vertices || b >= n_vertices || c >= n_vertices)
      throw InvalidInput(fmt::format("triangle {} refers to vertex {} of {}", t + 1,
                                     std::max({a, b, c}) + 1, n_vertices),
                         path);
    m.faces.row(t) << a, c, b;  // clockwise in MD2 -> counter-clockwise
  }
  for (int f = 0; f < n_frames; ++f) {
    std::size_t o = ofs_frames + static_cast<std::size_t>(frame_size) * static_cast<std::size_t>(f);
    float scale[3], translate[3];
    for (int k = 0; k < 3; ++k) {
      scale[k] = get<float>(d, o + 4u * static_cast<std::size_t>(k), path);
      translate[k] = get<float>(d, o + 12u + 4u * static_cast<std::size_t>(k), path);
    }
    char name[17] = {};
    std::memcpy(name, d.data() + o + 24, 16);
    Vertices V(n_vertices, 3);
    for (int v = 0; v < n_vertices; ++v) {
      std::size_t p = o + 40u + 4u * static_cast<std::size_t>(v);
      for (int k = 0; k < 3; ++k)
        V(v, k) = static_cast<double>(scale[k]) *
                      static_cast<unsigned char>(d[p + static_cast<std::size_t>(k)]) +
                  translate[k];
    }
    m.frames.push_back(std::move(V));
    m.frame_names.emplace_back(name);
    std::string stem = stem_of(name);
    if (m.animations.empty() || m.animations.back().name != stem)
      m.animations.push_back({stem, f, 0});
    ++m.animations.back().count;
  }
  return m;
}

}  // namespace df::io
