// export-gltf's job: a mesh sequence (an acap file with positions or features, or mesh files) as
// one animated glTF binary (io/gltf_file: morph targets and their animation), or one sequence of
// a skeleton file as animated joints.
#pragma once

#include <string>

#include "core/common_options.h"

namespace df::apps {

struct ExportGltfOptions {
  std::string input, output, sequence;
  double fps = 0;  ///< 0: a skeleton file's own frame rate, 30 for meshes
  int every = 1;
};

void export_gltf(const ExportGltfOptions& opt, const CommonOptions& common);

}  // namespace df::apps
