// edit-shape: edit a shape by dragging handle vertices, in the span of deformation components.
#include "apps/edit_shape.h"
#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "edit-shape",
      "Edit a shape by moving a few handle vertices, keeping it a combination of deformation\n"
      "components (data-driven deformation, the MSAE paper's §5 editing): the weights w of the\n"
      "components and the positions p minimise\n"
      "  Σ_ij c_ij ‖(p_i − p_j) − ½(T_i(w) + T_j(w))(q_i − q_j)‖² / Σ_ij c_ij ‖q_i − q_j‖² + "
      "λ‖w‖²\n"
      "with the handles held at their targets; T_i(w) = exp(Σ w_k ρ_ik)(S⁰_i + Σ w_k ΔS_ik) is "
      "the\n"
      "ACAP deformation the weights give vertex i (acap2obj's system, q the template). Solved by\n"
      "Levenberg-Marquardt on w, p eliminated (one factorisation per handle set).\n"
      "\n"
      "COMPONENTS: a components file (extract-components, prune-components, or fit-baseline\n"
      "--components-out for PCA or SPLOCS on ACAP features). Only the components that\n"
      "prune-components kept are used (--include-pruned: all).\n"
      "\n"
      "Multiscale editing, coarse then fine: --levels 0 moves only the coarse components; then\n"
      "--levels 1 --from that result adds a detail. The coarse step's weights are kept, and so "
      "are\n"
      "its handles: each stays where the coarse step put it (unless the new handle file moves it,\n"
      "or --release-handles frees them all), so that one detail handle cannot turn the rest of "
      "the\n"
      "shape about it. A model trained with train-msae's default soft penalty Ω often keeps no\n"
      "level-1 component after pruning (prune-components' report says 'level 1: 0 kept'): give\n"
      "--include-pruned to edit with them anyway, or train with --support proximal.\n"
      "\n"
      "OUTPUT: an acap .h5 with one frame (positions, raw and normalized features) and /edit:\n"
      "every component's weight, the handles and targets, the energy per step, and per handle\n"
      "the residual: its distance from the target in the shape the weights give with nothing\n"
      "held (how far the components reach it; the handles themselves sit on their targets).");
  tool.with_force();
  df::apps::EditShapeOptions opt;
  auto& app = tool.app();
  app.add_option("COMPONENTS", opt.components, "components .h5")->required();
  app.add_option(
      "--handles", opt.handles,
      "Text file, one handle per line: `vertex x y z` (a target) or `vertex` (held where\n"
      "it is); # starts a comment. Vertices count from 0");
  app.add_option(
         "--sample", opt.sample,
         "N handles spread over the template (furthest-point sampling from vertex 0), their\n"
         "targets taken from --to: a shape rebuilt from N control points (paper 2, Fig. 6)")
      ->check(CLI::PositiveNumber);
  app.add_option("--to", opt.to,
                 "--sample's targets: an acap .h5 with positions on the same template");
  app.add_option("--to-frame", opt.to_frame, "Which frame of --to")->default_val(opt.to_frame);
  app.add_option("--fixed", opt.fixed, "Vertices held where they are (comma-separated)")
      ->delimiter(',');
  app.add_option("--from", opt.from,
                 "Edit this shape (an acap .h5 on the components' template, e.g. an earlier edit,\n"
                 "whose weights are kept for the levels not edited now); default: the template");
  app.add_option("--from-frame", opt.from_frame, "Which frame of --from")
      ->default_val(opt.from_frame);
  app.add_option("--levels", opt.levels,
                 "Move only these levels' components (comma-separated; default: all)")
      ->delimiter(',');
  app.add_flag("--relative", opt.relative,
               "The handle file's x y z are displacements from where each vertex is in the shape\n"
               "edited from (drag by an amount)");
  app.add_flag("--include-pruned", opt.include_pruned,
               "Use the components prune-components dropped too (needed for a level whose\n"
               "components were all pruned)");
  app.add_flag("--release-handles", opt.release_handles,
               "With --from an earlier edit: do not hold that edit's handles where it put them");
  app.add_option("--l2", opt.solver.l2, "λ: weight of ‖w‖² (keeps underdetermined edits small)")
      ->default_val(opt.solver.l2)
      ->check(CLI::NonNegativeNumber);
  app.add_option(
         "--l1", opt.solver.l1,
         "μ: weight of a sparsity term Σ √(w² + 1e-6) (a smooth Σ|w|: few components active,\n"
         "as the ACAP paper's data-driven deformation); 0 = none")
      ->default_val(opt.solver.l1)
      ->check(CLI::NonNegativeNumber);
  app.add_option("--iterations", opt.solver.max_iterations, "Most solver steps")
      ->default_val(opt.solver.max_iterations)
      ->check(CLI::PositiveNumber);
  app.add_option("-o,--output", opt.output, "Output acap file (.h5)")->required();
  tool.footer(
      "Examples:\n"
      "  printf '120 0.1 0.9 0.3\\n"
      "0\\n"
      "' > h.txt     # drag vertex 120, hold vertex 0\n"
      "  edit-shape comps.h5 --handles h.txt -o edit.h5 && acap2obj edit.h5 -o edit/\n"
      "  edit-shape comps.h5 --handles h.txt --levels 0 -o coarse.h5            # coarse first\n"
      "  edit-shape comps.h5 --handles h2.txt --levels 1 --from coarse.h5 -o fine.h5   # then a "
      "detail,\n"
      "                                          # coarse.h5's handles held where it put them\n"
      "  edit-shape comps.h5 --sample 20 --to test.h5 --to-frame 3 -o fit.h5 && eval-metrics ...\n"
      "  edit-shape -v ...   # the energy at every step");
  return tool.run(argc, argv, [&] { df::apps::edit_shape(opt, tool.common()); });
}
