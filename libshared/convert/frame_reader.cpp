#include "convert/frame_reader.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "core/error.h"
#include "io/acap_file.h"
#include "io/frame_list.h"
#include "io/md2.h"
#include "io/mesh_io.h"
#include "io/schema.h"

namespace fs = std::filesystem;

namespace df::convert {

struct FrameReader::Source {
  enum class Kind { mesh_files, md2, hdf5 } kind;
  std::string path;
  std::vector<io::FrameSource> files;    // mesh_files
  io::Md2Model md2;                      // md2
  std::unique_ptr<io::AcapReader> file;  // hdf5
  Faces faces;                           // md2, hdf5: the connectivity of every frame
  std::size_t n_vertices = 0;
  std::string history;
};

namespace {
std::string dir_name(const fs::path& p) {
  fs::path d = p.has_filename() ? p : p.parent_path();
  return d.filename().string();
}
}  // namespace

FrameReader::FrameReader(const std::vector<std::string>& inputs) {
  if (inputs.empty()) throw UsageError("no inputs given");
  int pending = -1;  // source id of the running plain-file sequence (consecutive files share one)
  auto add_sequence = [&](std::string name, std::string label) {
    sequences_.push_back({std::move(name), std::move(label), frames_.size(), 0});
  };
  auto add_frame = [&](int source, std::size_t index, std::string name) {
    frames_.push_back({source, index, std::move(name)});
    ++sequences_.back().count;
  };
  for (const auto& input : inputs) {
    const int id = static_cast<int>(sources_.size());
    auto src = std::make_unique<Source>();
    src->path = input;
    if (input.empty() || input[0] != '@') {
      std::error_code ec;
      if (!fs::exists(input, ec)) throw IOError("no such file or directory", input);
    }
    if (input[0] != '@' && io::is_md2_file(input)) {
      pending = -1;
      src->kind = Source::Kind::md2;
      src->md2 = io::read_md2(input);
      src->faces = src->md2.faces;
      src->n_vertices = static_cast<std::size_t>(src->md2.frames.front().rows());
      for (const auto& a : src->md2.animations) {
        add_sequence(a.name, a.name);
        for (int f = a.first; f < a.first + a.count; ++f)
          add_frame(id, static_cast<std::size_t>(f),
                    src->md2.frame_names[static_cast<std::size_t>(f)]);
      }
    } else if (input[0] != '@' && io::is_hdf5_path(input)) {
      pending = -1;
      src->kind = Source::Kind::hdf5;
      src->file = std::make_unique<io::AcapReader>(input);
      if (!src->file->has_positions())
        throw InvalidInput("has no /frames/positions to compute features from", input);
      src->faces = src->file->read_faces();
      src->n_vertices = src->file->vertices();
      src->history = src->file->history();
      const auto names = src->file->frame_names();
      const auto seq_names = src->file->sequence_names();
      const auto offsets = src->file->offsets();
      const auto labels = src->file->sequence_labels();
      for (std::size_t s = 0; s < seq_names.size(); ++s) {
        add_sequence(seq_names[s], labels[s]);
        for (auto f = offsets[s]; f < offsets[s + 1]; ++f)
          add_frame(id, static_cast<std::size_t>(f), names[static_cast<std::size_t>(f)]);
      }
    } else {
      src->kind = Source::Kind::mesh_files;
      const bool single_file = input[0] != '@' && !fs::is_directory(input);
      src->files = io::expand_frames(input);
      if (single_file && pending >= 0) {  // continue the previous plain-file sequence
        auto& files = sources_[static_cast<std::size_t>(pending)]->files;
        files.push_back(src->files.front());
        add_frame(pending, files.size() - 1, files.back().name);
        continue;
      }
      std::string name = input[0] == '@' ? fs::path(input.substr(1)).stem().string()
                         : single_file   ? dir_name(fs::path(input).parent_path())
                                         : dir_name(fs::path(input));
      if (name.empty() || name == ".") name = "sequence";
      add_sequence(name, "");
      for (std::size_t f = 0; f < src->files.size(); ++f) add_frame(id, f, src->files[f].name);
      pending = single_file ? id : -1;
    }
    sources_.push_back(std::move(src));
  }
}

FrameReader::~FrameReader() = default;

std::size_t FrameReader::size() const {
  return frames_.size();
}

const std::string& FrameReader::frame_name(std::size_t i) const {
  return frames_[i].name;
}

std::string FrameReader::frame_origin(std::size_t i) const {
  const Frame& f = frames_[i];
  const Source& s = *sources_[static_cast<std::size_t>(f.source)];
  if (s.kind == Source::Kind::mesh_files) return s.files[f.index].path;
  return s.path + " frame " + f.name;
}

Mesh FrameReader::read(std::size_t i) const {
  const Frame& f = frames_[i];
  const Source& s = *sources_[static_cast<std::size_t>(f.source)];
  Mesh m;
  switch (s.kind) {
    case Source::Kind::mesh_files: {
      io::MeshReadReport rep;
      m = io::read_mesh(s.files[f.index].path, &rep);
      if (i == 0) io::warn_about(rep, s.files[f.index].path);
      return m;
    }
    case Source::Kind::md2:
      m.vertices = s.md2.frames[f.index];
      m.faces = s.faces;
      return m;
    case Source::Kind::hdf5: {
      std::vector<float> buf(s.n_vertices * 3);
      {
        std::lock_guard lock(hdf5_mutex_);
        s.file->read_positions(f.index, 1, buf.data());
      }
      m.vertices = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(
                       buf.data(), static_cast<Eigen::Index>(s.n_vertices), 3)
                       .cast<double>();
      m.faces = s.faces;
      return m;
    }
  }
  return m;
}

Vertices FrameReader::read_positions(std::size_t i, const Mesh& reference,
                                     const std::string& reference_name) const {
  const Frame& f = frames_[i];
  const Source& s = *sources_[static_cast<std::size_t>(f.source)];
  if (s.kind == Source::Kind::mesh_files) {
    const std::string& path = s.files[f.index].path;
    if (io::lower_extension(path) == ".obj")
      return io::read_obj_frame(path, reference, reference_name);
  }
  Mesh m = read(i);
  io::check_same_connectivity(reference, reference_name, m, frame_origin(i));
  return std::move(m.vertices);
}

std::vector<std::string> FrameReader::input_paths() const {
  std::vector<std::string> out;
  for (const auto& s : sources_) {
    if (s->kind == Source::Kind::mesh_files)
      for (const auto& f : s->files) out.push_back(f.path);
    else
      out.push_back(s->path);
  }
  return out;
}

std::vector<std::string> FrameReader::histories() const {
  std::vector<std::string> out;
  for (const auto& s : sources_)
    if (!s->history.empty()) out.push_back(s->history);
  return out;
}

}  // namespace df::convert
