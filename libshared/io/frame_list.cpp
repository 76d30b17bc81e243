#include "io/frame_list.h"

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "core/natural_sort.h"
#include "io/mesh_io.h"

namespace fs = std::filesystem;

namespace df::io {
namespace {

FrameSource source_of(const fs::path& p) {
  return {p.string(), p.stem().string()};
}

std::vector<FrameSource> from_directory(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && is_mesh_file(e.path().string()))
      names.push_back(e.path().filename().string());
  if (names.empty())
    throw InvalidInput("no mesh files (.obj, .off, .ply) in directory", dir.string());
  natural_sort(names);
  std::vector<FrameSource> out;
  for (const auto& n : names) out.push_back(source_of(dir / n));
  return out;
}

std::vector<FrameSource> from_list(const fs::path& list) {
  std::ifstream in(list);
  if (!in)
    throw IOError(fs::exists(list) ? "cannot read list file" : "no such list file", list.string());
  std::vector<FrameSource> out;
  int lineno = 0;
  for (std::string line; std::getline(in, line);) {
    ++lineno;
    auto b = line.find_first_not_of(" \t\r");
    if (b == std::string::npos || line[b] == '#') continue;
    auto e = line.find_last_not_of(" \t\r");
    fs::path p = line.substr(b, e - b + 1);
    if (p.is_relative()) p = list.parent_path() / p;
    std::error_code ec;
    if (!fs::exists(p, ec))
      throw IOError("listed path does not exist: " + p.string(),
                    list.string() + ":" + std::to_string(lineno));
    if (fs::is_directory(p, ec)) {
      auto d = from_directory(p);
      out.insert(out.end(), d.begin(), d.end());
    } else if (!is_mesh_file(p.string())) {
      throw InvalidInput("listed file is not a mesh file (.obj, .off, .ply): " + p.string(),
                         list.string() + ":" + std::to_string(lineno));
    } else {
      out.push_back(source_of(p));
    }
  }
  if (out.empty()) throw InvalidInput("list file names no frames", list.string());
  return out;
}

}  // namespace

std::vector<FrameSource> expand_frames(const std::string& input) {
  if (!input.empty() && input[0] == '@') return from_list(input.substr(1));
  fs::path p = input;
  std::error_code ec;
  if (!fs::exists(p, ec)) throw IOError("no such file or directory", input);
  if (fs::is_directory(p, ec)) return from_directory(p);
  if (!is_mesh_file(input))
    throw InvalidInput(
        "unknown input format: expected a mesh file (.obj, .off, .ply), an MD2 model (.md2), an "
        "acap .h5 file, a directory of mesh files or an @LIST of them",
        input);
  return {source_of(p)};
}

std::vector<FrameSource> expand_frames(const std::vector<std::string>& inputs) {
  std::vector<FrameSource> out;
  for (const auto& in : inputs) {
    auto f = expand_frames(in);
    out.insert(out.end(), f.begin(), f.end());
  }
  return out;
}

}  // namespace df::io
