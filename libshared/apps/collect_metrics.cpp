#include "apps/collect_metrics.h"

#include <filesystem>
#include <iostream>
#include <sstream>

#include "core/atomic_output.h"
#include "core/error.h"
#include "eval/metrics_table.h"

namespace df::apps {
using namespace df::eval;

void collect_metrics_tool(const CollectMetricsOptions& opt) {
  if (opt.values && opt.columns.empty())
    throw UsageError("--values needs --columns (the values to print)");
  const std::vector<std::filesystem::path> inputs(opt.files.begin(), opt.files.end());
  const auto claims = claim_outputs({opt.output}, opt.force, inputs);
  const MetricsTable table = collect_metrics(opt.files, opt.names, opt.columns, opt.values);
  std::ostringstream text;
  write_tsv(text, table, opt.values);
  if (opt.output.empty() || opt.output == "-")
    std::cout << text.str();
  else
    write_text_output(opt.output, text.str(), opt.force, inputs);
}

}  // namespace df::apps
