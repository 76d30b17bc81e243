// acap2obj: ACAP features -> meshes (reconstruction).
#include "convert/acap2obj.h"

#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "acap2obj",
      "Reconstruct meshes from ACAP features (acap file kind, from obj2acap, gen-bdlstm\n"
      "or recon-msae): de-normalize with the stored numbers, rebuild T = exp(L)·S per\n"
      "vertex and solve for positions (--solver) with one pinned vertex per connected\n"
      "component. The system matrix is factored once per template; frames are solved\n"
      "in parallel.\n"
      "\n"
      "OUTPUT: a directory of mesh files (format from --name's extension), or NAME.h5\n"
      "(acap kind with the reconstructed /frames/positions; the features stay in INPUT).\n"
      "When the input stores original positions, the round-trip error is reported.");
  tool.with_force();
  df::convert::Acap2ObjOptions opt;
  auto& app = tool.app();
  app.add_option("INPUT", opt.input, "acap .h5 file with features")->required();
  app.add_option("-o,--output", opt.output, "Output directory, or .h5 file")->required();
  app.add_option("--frames", opt.frames,
                 "Frames to reconstruct, global indices: 0-9,20,30- (default all)");
  app.add_option("--sequence", opt.sequences,
                 "Only frames of these sequences (repeatable, or comma-separated)")
      ->delimiter(',')
      ->allow_extra_args(false);
  app.add_option(
      "--name", opt.name_pattern,
      "File name pattern with {name} {index} {sequence} (fmt syntax, e.g.\n"
      "'{index:04d}.ply'); default {name}.obj, or {sequence}-{name}.obj when names repeat");
  app.add_option("--features", opt.features, "raw, normalized, or auto (raw when present)")
      ->default_val(opt.features)
      ->check(CLI::IsMember({"raw", "normalized", "auto"}));
  app.add_option("--anchor", opt.anchor, "Vertex pinned in its component")
      ->default_val(opt.anchor)
      ->check(CLI::NonNegativeNumber);
  app.add_option("--anchor-positions", opt.anchor_positions,
                 "Where pinned vertices go: reference (template position), frames (the stored\n"
                 "original position of the frame), auto (frames when stored, else reference)")
      ->default_val(opt.anchor_positions)
      ->check(CLI::IsMember({"auto", "reference", "frames"}));
  app.add_option("--solver", opt.solver,
                 "gradients: positions whose deformation gradients reproduce the features\n"
                 "(exact for features of a real mesh; see the README). edges: the SPEC/paper\n"
                 "system min Σ w‖(p'_i − p'_j) − ½(T_i + T_j)(p_i − p_j)‖², exact only where\n"
                 "one-rings deform affinely")
      ->default_val(opt.solver)
      ->check(CLI::IsMember({"gradients", "edges"}));
  tool.footer(
      "Examples:\n"
      "  acap2obj horse.h5 -o horse-meshes/\n"
      "  acap2obj --solver edges horse.h5 -o paper/   # the papers' reconstruction\n"
      "  acap2obj gen.h5 --frames 0-99 --name '{index:04d}.ply' -o frames/\n"
      "  acap2obj faerie.h5 --sequence run -o run.h5");
  return tool.run(argc, argv, [&] { df::convert::acap2obj(opt, tool.common()); });
}
