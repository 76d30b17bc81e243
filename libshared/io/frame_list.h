// Turning command-line inputs into an ordered list of mesh frames: a file is one frame, a
// directory gives its mesh files in natural order (2.obj before 10.obj), and @LIST reads one
// path per line (relative to the list's directory; blank lines and # comments skipped).
#pragma once

#include <string>
#include <vector>

namespace df::io {

struct FrameSource {
  std::string path;  ///< the mesh file
  std::string name;  ///< its file name without extension (the frame's name)
};

/// Expands one input (file, directory or @list) into frames. Throws IOError/InvalidInput for a
/// missing path, a directory without mesh files, or a list naming a missing file (with line).
std::vector<FrameSource> expand_frames(const std::string& input);

/// Expands several inputs, in order.
std::vector<FrameSource> expand_frames(const std::vector<std::string>& inputs);

}  // namespace df::io
