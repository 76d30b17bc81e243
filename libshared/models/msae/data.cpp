#include "models/msae/data.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/atomic_output.h"
#include "core/error.h"
#include "io/file_header.h"
#include "io/schema.h"

namespace df::models {

MsaeShapes read_msae_shapes(const MsaeModel& m, const std::string& path, const std::string& part) {
  io::Dimensions dims;
  h5::File in = io::open_input(path, "acap", &dims);
  if (!in.exists("/features/normalized"))
    throw InvalidInput("has no /features/normalized; run obj2acap on the meshes first", path);
  const io::Faces faces = in.read_matrix<int>("/template/faces");
  const auto V = static_cast<std::size_t>(m.tmpl.vertices.rows());
  if (dims.at("V") != V || faces.rows() != m.tmpl.faces.rows() || faces != m.tmpl.faces)
    throw InvalidInput(
        fmt::format(
            "has another template than the model ({} vertices, {} triangles; the model's: {}, "
            "{}): the model only works on shapes of its own template",
            dims.at("V"), faces.rows(), V, m.tmpl.faces.rows()),
        path);
  const auto n = static_cast<std::int64_t>(dims.at("N"));
  MsaeShapes s;
  if (part == "all") {
    for (std::int64_t f = 0; f < n; ++f) s.frames.push_back(f);
  } else {
    if (part == "train")
      s.frames = m.split.train;
    else if (part == "validation")
      s.frames = m.split.validation;
    else if (part == "test")
      s.frames = m.split.test;
    else
      throw UsageError("--part must be train, validation, test or all");
    for (auto f : s.frames)
      if (f >= n)
        throw InvalidInput(
            fmt::format(
                "has {} frames, but the model's {} part names frame {}: give the file it was "
                "trained on ({}), or --part all",
                n, part, f, m.split.data),
            path);
  }
  s.history = io::read_history(in);
  const auto offsets = in.read<std::int64_t>("/sequences/offsets").data;
  const auto sequences = in.read_strings("/sequences/names");
  const auto names = in.read_strings("/frames/names");
  const geometry::Normalization nz = geometry::read_normalization(in);
  const bool renormalize = nz.min != m.normalization.min || nz.max != m.normalization.max;
  s.x.resize(static_cast<Eigen::Index>(s.frames.size()), 9 * static_cast<Eigen::Index>(V));
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    const auto f = s.frames[k];
    in.read_rows<float>("/features/normalized", static_cast<std::size_t>(f), 1,
                        s.x.row(static_cast<Eigen::Index>(k)).data());
    io::check_finite_rows(s.x.row(static_cast<Eigen::Index>(k)).data(), static_cast<std::size_t>(f),
                          1, 9 * V, in.where("/features/normalized"));
    if (renormalize)
      for (Eigen::Index j = 0; j < s.x.cols(); ++j) {
        const int d = static_cast<int>(j % 9);
        float& v = s.x(static_cast<Eigen::Index>(k), j);
        v = static_cast<float>(m.normalization.normalize(d, nz.denormalize(d, v)));
      }
    s.names.push_back(names[static_cast<std::size_t>(f)]);
    // The sequence whose [offsets[q], offsets[q + 1]) holds frame f.
    const auto q = std::upper_bound(offsets.begin(), offsets.end(), f) - offsets.begin() - 1;
    s.sequence.push_back(sequences[static_cast<std::size_t>(q)]);
  }
  return s;
}

void write_shapes(const std::string& path, const MsaeModel& m, const MsaeShapes& shapes,
                  const nn::Matrix<float>* features, const nn::Matrix<float>* positions,
                  const std::string& data, const std::vector<std::string>& inputs, bool force,
                  const std::string& method) {
  std::vector<std::filesystem::path> in(inputs.begin(), inputs.end());
  AtomicOutput dest(path, AtomicOutput::Kind::file, force, in);
  {
    h5::File f(dest.temp_path(), h5::File::Mode::create, path);
    io::write_header(f, "acap",
                     {m.history == shapes.history ? m.history : m.history + "\n" + shapes.history});
    f.write_matrix("/template/vertices", m.tmpl.vertices);
    f.write_matrix("/template/faces", m.tmpl.faces);
    geometry::write_normalization(f, m.normalization);
    // One sequence per data sequence that has frames here, in file order.
    std::vector<std::string> seqs;
    std::vector<std::int64_t> offsets{0};
    for (std::size_t k = 0; k < shapes.sequence.size(); ++k) {
      if (seqs.empty() || seqs.back() != shapes.sequence[k]) {
        if (!seqs.empty()) offsets.push_back(static_cast<std::int64_t>(k));
        seqs.push_back(shapes.sequence[k]);
      }
    }
    offsets.push_back(static_cast<std::int64_t>(shapes.sequence.size()));
    const auto n = shapes.frames.size(), V = static_cast<std::size_t>(m.tmpl.vertices.rows());
    f.write_strings("/frames/names", shapes.names);
    f.write<std::int64_t>("/frames/source", shapes.frames, {n});
    f.set_attr("/frames/source", "data", data);
    f.set_attr("/frames/source", "method", method);
    f.write<std::int64_t>("/sequences/offsets", offsets, {offsets.size()});
    f.write_strings("/sequences/names", seqs);
    if (features)
      f.write<float>("/features/normalized", std::span<const float>(features->data(), n * V * 9),
                     {n, V, 9});
    if (positions)
      f.write<float>("/frames/positions", std::span<const float>(positions->data(), n * V * 3),
                     {n, V, 3});
    f.close();
  }
  dest.commit();
}

}  // namespace df::models
