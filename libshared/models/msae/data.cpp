#include "models/msae/data.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/atomic_output.h"
#include "core/error.h"
#include "io/acap_file.h"
#include "models/common/model_data.h"

namespace df::models {

MsaeShapes read_msae_shapes(const MsaeModel& m, const std::string& path, FramePart part) {
  const ModelData data(path, m.tmpl);
  const auto n = static_cast<std::int64_t>(data.frames());
  MsaeShapes s;
  if (part == FramePart::all) {
    for (std::int64_t f = 0; f < n; ++f) s.frames.push_back(f);
  } else {
    s.frames = part == FramePart::train        ? m.split.train
               : part == FramePart::validation ? m.split.validation
                                               : m.split.test;
    for (auto f : s.frames)
      if (f >= n)
        throw InvalidInput(fmt::format("has {} frames, but the model's {} part names frame {}: "
                                       "give the file it was trained on ({}), or --part all",
                                       n, part, f, m.split.data),
                           path);
  }
  s.history = data.file().history();
  s.offsets = data.file().offsets();
  s.sequences = data.file().sequence_names();
  const auto names = data.file().frame_names();
  s.x = data.features(s.frames, m.normalization);
  for (const auto f : s.frames) {
    s.names.push_back(names[static_cast<std::size_t>(f)]);
    // The sequence whose [offsets[q], offsets[q + 1]) holds frame f.
    const auto q = std::upper_bound(s.offsets.begin(), s.offsets.end(), f) - s.offsets.begin() - 1;
    s.sequence.push_back(s.sequences[static_cast<std::size_t>(q)]);
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
    io::AcapWriter f(dest.temp_path(), path,
                     {m.history == shapes.history ? m.history : m.history + "\n" + shapes.history});
    f.write_template(m.tmpl);
    f.write_normalization(m.normalization);
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
    f.write_frame_names(shapes.names);
    f.write_source(shapes.frames, data, method);
    f.write_sequences(offsets, seqs);
    if (features) f.write_normalized(n, V, features->data());
    if (positions) f.write_positions(n, V, positions->data());
    f.close();
  }
  dest.commit();
}

}  // namespace df::models
