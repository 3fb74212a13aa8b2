#pragma once
// The pieces of a campaign shared by the local scheduler (campaign.cpp) and the MPI one
// (campaign_mpi.cpp): the checked design and its rows, starting one run, and reading back
// what it produced.

#include <sys/types.h>

#include <string>
#include <vector>

#include "bushel/doe/campaign.hpp"

namespace bushel::doe::detail {

struct Row {
  int std_order = 0;
  std::vector<std::string> values;  // as written in the design, one per column
  std::vector<double> responses;
  std::string status = "pending";
};

struct Campaign {
  CampaignSpec spec;
  std::vector<std::string> header;
  std::vector<Row> rows;          // in standard order
  std::vector<std::size_t> todo;  // rows to run, in run order
  std::vector<std::string> env;   // the runs' environment (OMP_NUM_THREADS set)
  std::string results;            // results table path
  int skipped = 0;
};

/// Reads and checks everything (design, placeholders) before anything runs, creates the
/// directory, finds the finished rows and (if `write`) writes the results table.
Campaign prepare(const CampaignSpec& spec, int threads_per_run, bool write = true);
/// Starts row i's run in its freshly emptied directory; returns the child's pid.
pid_t start_run(const Campaign& c, std::size_t i);
/// Records row i's outcome from the exit status of its process: done (responses read from
/// its JSON output, done.json written atomically) or failed.
void finish_run(Campaign& c, std::size_t i, int wait_status);
/// Rewrites the results table (atomically).
void write_results(const Campaign& c);
/// Cores / runs at a time, at least 1, unless the spec sets threads.
int threads_per_run(const CampaignSpec& spec, int runs_at_a_time);

#ifdef BUSHEL_HAVE_MPI
/// True when this process is one of several started by mpirun.
bool launched_by_mpi();
/// The campaign over MPI ranks: rank 0 hands out rows and keeps the results table, the other
/// ranks run them (one at a time each) and report back.
CampaignReport run_campaign_mpi(const CampaignSpec& spec, bool progress);
#endif

}  // namespace bushel::doe::detail
