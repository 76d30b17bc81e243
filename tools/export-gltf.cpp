// export-gltf: a mesh sequence as one animated glTF 2.0 binary for Blender and web viewers.
#include "apps/export_gltf.h"
#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "export-gltf",
      "Write a mesh sequence as one glTF 2.0 binary (.glb) that animation tools play: the first\n"
      "frame is the mesh, every frame a morph target (positions and normals), and one animation\n"
      "switches the targets on in turn (frame k at time k / fps, linear between frames).\n"
      "\n"
      "INPUT: an acap .h5 (stored positions, or reconstructed from its features as acap2obj\n"
      "does: gen-bdlstm and recon-msae outputs) or mesh files / directories; or a skeleton .h5\n"
      "(skel2h5, gen-actgan): one sequence as animated joints, a node per joint in the\n"
      "skeleton's hierarchy, its normalization undone.\n"
      "Blender: File > Import > glTF 2.0, then play the timeline; three.js and other viewers\n"
      "open the file directly.");
  tool.with_force();
  df::apps::ExportGltfOptions opt;
  auto& app = tool.app();
  app.add_option("INPUT", opt.input, "acap .h5, or mesh files / directories")->required();
  app.add_option("-o,--output", opt.output, "Output .glb")->required();
  app.add_option(
      "--fps", opt.fps,
      "Frame rate of the input (default: a skeleton file's own, 30 for meshes); with --every K\n"
      "the kept frames play at the same speed");
  app.add_option(
      "--sequence", opt.sequence,
      "Only this sequence (by name, or index when no name matches; default: every frame of\n"
      "meshes, a skeleton file's first sequence)");
  app.add_option("--every", opt.every, "Every K-th frame")->default_val(opt.every);
  tool.footer(
      "Examples:\n"
      "  export-gltf gen.h5 -o walk.glb            # a generated sequence\n"
      "  export-gltf horse.h5 --fps 24 -o horse.glb\n"
      "  export-gltf meshes/ --every 2 -o seq.glb\n"
      "  export-gltf generated-actions.h5 --sequence 3 -o kick.glb   # a skeleton sequence");
  return tool.run(argc, argv, [&] { df::apps::export_gltf(opt, tool.common()); });
}
