// Provenance: every HDF5 output carries a `history` attribute, one line per tool that touched
// the data ("ISO-time command line"), newest first, inherited from the inputs (NCO's
// `history`, samtools' @PG). SOURCE_DATE_EPOCH, when set, fixes the time for reproducible bytes.
#pragma once

#include <string>
#include <vector>

namespace df::provenance {

/// Records the running tool's command line (shell-quoted where needed). Called by the wrapper.
void set_command_line(int argc, const char* const* argv);
const std::string& command_line();

/// UTC time as 2026-11-22T14:03:07Z; SOURCE_DATE_EPOCH overrides the clock.
std::string now_iso8601();

/// The history for a new output: this run's line first, then the inputs' histories in input
/// order (each a newline-separated list, newest first), exact duplicates dropped.
std::string history(const std::vector<std::string>& inherited = {});

/// Splits a history attribute into its lines.
std::vector<std::string> history_lines(const std::string& history);

}  // namespace df::provenance
