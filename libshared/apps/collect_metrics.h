// collect-metrics' job: eval's metrics table of many JSON files, as TSV to a file or stdout.
#pragma once

#include <string>
#include <vector>

namespace df::apps {

struct CollectMetricsOptions {
  std::vector<std::string> files;
  std::vector<std::string> names;
  std::vector<std::string> columns;  ///< "" = every number found
  bool values = false;               ///< only the cells; every value must exist
  std::string output;                ///< "" or "-" = stdout
  bool force = false;
};

/// collect-metrics: collect_metrics, then the TSV to the output (atomically) or stdout.
void collect_metrics_tool(const CollectMetricsOptions& opt);

}  // namespace df::apps
