// obj2acap: mesh frames -> ACAP deformation features (acap file kind).
#include "convert/obj2acap.h"

#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "obj2acap",
      "Compute ACAP (as-consistent-as-possible) deformation features of mesh frames\n"
      "(Gao et al., 'Sparse Data Driven Mesh Deformation', TVCG 2019), the representation\n"
      "the BD-LSTM and MSAE methods learn on. Per vertex: r (3, log of the rotation, made\n"
      "consistent across neighbours and time) and s (6, the symmetric stretch).\n"
      "\n"
      "INPUT (one or more; all frames must share the reference's connectivity):\n"
      "  DIR          mesh files (.obj .off .ply) in natural order: one sequence\n"
      "  @LIST        a text file naming one mesh file or directory per line: one sequence\n"
      "  FILE...      consecutive mesh files: one sequence\n"
      "  MODEL.md2    Quake II keyframe model: one labelled sequence per animation\n"
      "  FRAMES.h5    an acap file with /frames/positions (e.g. from synth-meshseq)\n"
      "OUTPUT: an acap .h5 with /template, /frames/positions, /features/raw [N,V,9] f64,\n"
      "/features/normalized [N,V,9] f32 in [-0.95,0.95], /normalization, /sequences.");
  tool.with_force();
  df::convert::Obj2AcapOptions opt;
  std::string normalize = "group";
  bool no_consistency = false;
  auto& app = tool.app();
  app.add_option("INPUT", opt.inputs, "Frames: directories, @lists, mesh files, .md2, acap .h5")
      ->required();
  app.add_option("-o,--output", opt.output, "Output acap file (.h5)")->required();
  app.add_option("--reference", opt.reference, "Reference mesh (default: the first frame)");
  app.add_option("--normalize", normalize,
                 "group: one min/max over all r entries and one over all s entries (as the\n"
                 "authors' code); per-dim: each of the 9 dimensions separately")
      ->default_val(normalize)
      ->check(CLI::IsMember({"group", "per-dim"}));
  app.add_option("--labels", opt.labels,
                 "One class label per sequence (comma-separated), e.g. walk,run")
      ->delimiter(',')
      ->allow_extra_args(false);
  app.add_flag("--no-consistency", no_consistency,
               "Store each vertex's principal rotation log (no ACAP consistency; for comparison)");
  app.add_option("--max-sweeps", opt.consistency_options.max_sweeps,
                 "Bound on consistency improvement sweeps per frame (deterministic time bound)")
      ->default_val(opt.consistency_options.max_sweeps)
      ->check(CLI::PositiveNumber);
  tool.footer(
      "Examples:\n"
      "  obj2acap horse/ -o horse.h5\n"
      "  obj2acap walk/ run/ --labels walk,run -o moves.h5\n"
      "  obj2acap /usr/share/assimp/models/MD2/faerie.md2 -o faerie.h5\n"
      "  obj2acap -v frames/ -o f.h5    # prints both consistency objectives per frame\n"
      "Reconstruct meshes with acap2obj; inspect with h5check.");
  return tool.run(argc, argv, [&] {
    opt.normalize =
        normalize == "group" ? df::NormalizationMode::group : df::NormalizationMode::per_dim;
    opt.consistency = !no_consistency;
    df::convert::obj2acap(opt, tool.common());
  });
}
