// The frames of obj2acap's inputs, grouped into sequences:
//   * a directory (natural order) or an @LIST file: one sequence, named after it;
//   * consecutive plain mesh files: one sequence, named after the first file's directory;
//   * an MD2 model (.md2): one labelled sequence per named animation;
//   * an acap .h5 file with /frames/positions (e.g. from synth-meshseq): its sequences, names
//     and labels.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "io/mesh_io.h"

namespace df::convert {

struct SequenceInfo {
  std::string name;
  std::string label;  ///< "" = unlabelled
  std::size_t first = 0, count = 0;
};

class FrameReader {
 public:
  explicit FrameReader(const std::vector<std::string>& inputs);
  ~FrameReader();

  std::size_t size() const;
  const std::vector<SequenceInfo>& sequences() const { return sequences_; }
  const std::string& frame_name(std::size_t i) const;
  /// Where frame i comes from, for messages ("walk/17.obj", "faerie.md2 frame run3").
  std::string frame_origin(std::size_t i) const;
  /// Reads frame i with its connectivity (mesh files are read on demand; MD2 and HDF5 frames
  /// come from memory or the open file). Thread-safe.
  Mesh read(std::size_t i) const;
  /// Reads frame i's positions, checking that it has `reference`'s connectivity (OBJ files go
  /// through the fast parser). Thread-safe; frames may be read in parallel.
  Vertices read_positions(std::size_t i, const Mesh& reference,
                          const std::string& reference_name) const;
  /// Inputs that are files (for the "do not overwrite an input" check).
  std::vector<std::string> input_paths() const;
  /// Histories of HDF5 inputs (provenance).
  std::vector<std::string> histories() const;

 private:
  struct Source;
  std::vector<std::unique_ptr<Source>> sources_;
  struct Frame {
    int source;
    std::size_t index;
    std::string name;
  };
  std::vector<Frame> frames_;
  std::vector<SequenceInfo> sequences_;
  mutable std::mutex hdf5_mutex_;  // the serial HDF5 library is not thread-safe
};

}  // namespace df::convert
