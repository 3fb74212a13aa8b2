#pragma once
// A campaign: one run of a command per row of a design, several at a time, each in its own
// directory, the responses read from the command's JSON output into one results table.
// Resumable: a run that finished has a done.json (written atomically, with its responses);
// starting the campaign again skips those and reruns the rest from scratch, so a kill at
// any moment loses at most the runs in flight and never corrupts a finished one. The results
// table is rewritten atomically after every run.

#include <string>
#include <vector>

namespace bushel::doe {

struct CampaignSpec {
  std::string design;                  ///< CSV of runs (std_order and factor columns)
  std::string out;                     ///< campaign directory
  std::vector<std::string> command;    ///< program and arguments; {column} is replaced by the
                                       ///< row's value, {run_dir} by its directory, {bushel}
                                       ///< by this program
  std::vector<std::string> responses;  ///< keys in the command's JSON output ("a.b" nests)
  std::string response_root;           ///< where the keys are: "" the output's top, "results" under it
  int jobs = 1;                        ///< runs at a time
  int threads = 0;                     ///< OpenMP threads per run (0: cores / jobs, at least 1)
};

struct CampaignReport {
  int runs = 0, skipped = 0, ran = 0, failed = 0;
  std::string results;      ///< path of the results table
  bool coordinator = true;  ///< false on the MPI ranks that only ran rows (they report nothing)
};

/// Checks the spec (the design's columns, every placeholder) before anything runs, then runs
/// the missing rows: `jobs` at a time here, or, when started by `mpirun -n K` in a build with
/// MPI, on ranks 1..K-1 with rank 0 handing out the rows (the campaign directory must be on a
/// file system all ranks see). Throws InputError for a bad spec; failed runs are reported,
/// not thrown.
CampaignReport run_campaign(const CampaignSpec& spec, bool progress = true);

}  // namespace bushel::doe
