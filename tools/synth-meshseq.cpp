// synth-meshseq: procedural mesh sequences with known structure (no data download needed).
#include "core/tool.h"
#include "synth/meshseq.h"

int main(int argc, char** argv) {
  df::Tool tool("synth-meshseq",
                "Make a procedural mesh sequence with known structure:\n"
                "  finger  a capped cylinder that bends (amplitude x 90 deg) and twists (--twist\n"
                "          degrees at the tip, may exceed 180 or 360) periodically;\n"
                "  flag    a cloth grid pinned at one side with travelling waves;\n"
                "  bumps   a surface with planted localized deformations at two scales (2 coarse,\n"
                "          --fine-regions fine ones), each frame a random mix; regions, centres\n"
                "          and weights are stored under /synthetic as ground truth.\n"
                "Output: -o NAME.h5 writes the 'acap' file kind with /template and\n"
                "/frames/positions (features are added later by obj2acap); any other -o is a\n"
                "directory of mesh files 0000.obj, 0001.obj, ... (--mesh-format).");
  tool.with_seed(0).with_force();
  df::synth::MeshSeqParams p;
  std::string kind = "finger", output, format = "obj";
  auto& app = tool.app();
  app.add_option("--kind", kind, "finger, flag or bumps")
      ->default_val(kind)
      ->check(CLI::IsMember({"finger", "flag", "bumps"}));
  app.add_option("--frames", p.frames, "Frames per sequence")
      ->default_val(p.frames)
      ->check(CLI::PositiveNumber);
  app.add_option("--sequences", p.sequences,
                 "Independent variations (amplitude x0.7..1.3), stored one after another")
      ->default_val(p.sequences)
      ->check(CLI::PositiveNumber);
  app.add_option("--resolution", p.resolution,
                 "finger: vertices around (4x as many rings); grids: quads per side")
      ->default_val(p.resolution)
      ->check(CLI::Range(3, 4096));
  app.add_option("--amplitude", p.amplitude, "Deformation scale")->default_val(p.amplitude);
  app.add_option("--twist", p.twist_degrees, "finger: tip twist in degrees at the peak")
      ->default_val(p.twist_degrees);
  app.add_option("--periods", p.periods, "Motion periods per sequence")->default_val(p.periods);
  app.add_option("--fine-regions", p.fine_regions,
                 "bumps: fine regions beside the 2 coarse ones (more regions than a model's first "
                 "level has components make it place fine ones on its second)")
      ->default_val(p.fine_regions)
      ->check(CLI::Range(0, df::synth::kMaxFineRegions));
  app.add_option("--mesh-format", format, "Mesh files when -o is a directory: obj, ply, off")
      ->default_val(format)
      ->check(CLI::IsMember({"obj", "ply", "off"}));
  app.add_option("-o,--output", output, "Output: NAME.h5 (acap kind) or a directory")->required();
  tool.footer(
      "Examples:\n"
      "  synth-meshseq --kind finger --twist 400 --frames 120 -o finger.h5\n"
      "  synth-meshseq --kind bumps --frames 500 -o bumps.h5 && h5check bumps.h5\n"
      "  synth-meshseq --kind bumps --fine-regions 12 --resolution 40 -o bumps14.h5\n"
      "  synth-meshseq --kind flag -o flag-frames/   # OBJ files for obj2acap");
  return tool.run(argc, argv, [&] {
    p.kind = df::synth::mesh_seq_kind_from_name(kind);
    p.seed = tool.common().seed;
    df::synth::synth_meshseq(p, output, format, tool.common());
  });
}
