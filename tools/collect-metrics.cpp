// collect-metrics: one table from the metrics JSON of many runs (a sweep's tasks).
#include "apps/collect_metrics.h"
#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "collect-metrics",
      "Gather the metrics of many runs into one table: each FILE is the JSON that\n"
      "eval-metrics --json wrote (or any JSON object); its numbers become the columns, named\n"
      "by their path (E_rms, sted.spatial, ...; lists such as per-step errors are left out),\n"
      "one row per file, named by the file's directory (sweep/kz10/metrics.json -> kz10) or\n"
      "by --names. A number one file lacks is an empty cell. scripts/sweep calls it as the\n"
      "collect step of a parameter sweep.\n"
      "\n"
      "OUTPUT: a tab-separated table (header row 'name' + columns) on stdout or to -o.");
  tool.with_force();
  df::apps::CollectMetricsOptions opt;
  auto& app = tool.app();
  app.add_option("FILE", opt.files, "Metrics JSON files, one row each")->required();
  app.add_option("--names", opt.names, "Row names, one per file (comma-separated)")
      ->delimiter(',')
      ->allow_extra_args(false);
  app.add_option(
         "--columns", opt.columns,
         "Only these columns, in this order (comma-separated paths: members by name, array\n"
         "elements by index, e.g. erms,sted.spatial,levels.1.kept; strings and booleans too)")
      ->delimiter(',')
      ->allow_extra_args(false);  // one comma-separated word: the files follow
  app.add_flag(
      "--values", opt.values,
      "Print the cells alone (no header, no row names); each file must have every column.\n"
      "What a script or Makefile reads instead of a tool's human-readable table");
  app.add_option("-o,--output", opt.output, "Output table (.tsv); default stdout");
  tool.footer(
      "Examples:\n"
      "  collect-metrics sweep/*/metrics.json -o sweep/table.tsv\n"
      "  collect-metrics a.json b.json --names joint,separate | column -t\n"
      "  erms=$(collect-metrics --values --columns erms recon.json)   # one number, in a script");
  return tool.run(argc, argv, [&] {
    opt.force = tool.common().force;
    df::apps::collect_metrics_tool(opt);
  });
}
