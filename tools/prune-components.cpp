// prune-components: drop the weak components of an MSAE (paper 2, §4.3).
#include "apps/msae_components.h"
#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "prune-components",
      "Redundant component removal (paper 2, section 4.3): a component's strength is the\n"
      "mean of |(X - X_r)_i| over the vertices where it exceeds --eps1 (eq. 7; X_r the\n"
      "reference's features, normalized units); components weaker than --eps2 are marked\n"
      "dropped. Prints a table per component and the kept/dropped count per level.\n"
      "\n"
      "INPUT: a components .h5 from extract-components (or an earlier prune-components).\n"
      "OUTPUT: the same file with /level<l>/kept and strength updated; --acap writes the kept\n"
      "components as an acap file, --json the report.");
  tool.with_force();
  df::apps::PruneOptions opt;
  auto& app = tool.app();
  app.add_option("INPUT", opt.input, "components .h5")->required();
  app.add_option("-o,--output", opt.output, "Output components file (.h5)")->required();
  app.add_option("--eps1", opt.eps1, "Per-vertex threshold of eq. 7")->default_val(opt.eps1);
  app.add_option("--eps2", opt.eps2, "Keep components at least this strong")->default_val(opt.eps2);
  app.add_option("--acap", opt.acap, "Also write the kept components as an acap file");
  app.add_option("--json", opt.json, "Also write the report as JSON");
  tool.footer(
      "Examples:\n"
      "  prune-components comps.h5 -o kept.h5\n"
      "  prune-components --eps2 0.05 comps.h5 -o kept.h5 --acap kept-acap.h5 --json report.json");
  return tool.run(argc, argv, [&] { df::apps::prune_components_tool(opt, tool.common()); });
}
