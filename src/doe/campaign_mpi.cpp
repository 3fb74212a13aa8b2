// The campaign across MPI ranks (built with BUSHEL_ENABLE_MPI): rank 0 hands out rows in run
// order and keeps the results table; every other rank runs one row at a time and reports its
// outcome. Messages: a worker sends [row, done, responses...] (row -1: ready for the first);
// rank 0 answers with the next row, or -1 when none is left.
#include <mpi.h>
#include <sys/wait.h>

#include <fmt/format.h>
#include <cerrno>
#include <cstdlib>
#include <string>
#include <vector>

#include "campaign_run.hpp"

namespace bushel::doe::detail {

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"}) {
    if (const char* v = std::getenv(name); v != nullptr && std::atoi(v) > 1) return true;
  }
  return false;
}

namespace {
constexpr int tag_result = 1, tag_row = 2;

int local_ranks() {
  const char* v = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  return v != nullptr ? std::max(1, std::atoi(v)) : 1;
}
}  // namespace

CampaignReport run_campaign_mpi(const CampaignSpec& spec, bool progress) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (initialized == 0) MPI_Init(nullptr, nullptr);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const int n_responses = static_cast<int>(spec.responses.size());
  CampaignReport report;
  // Every rank checks the spec; rank 0 alone writes. The ranks of one machine share its cores.
  Campaign c = prepare(spec, threads_per_run(spec, local_ranks()), rank == 0);
  MPI_Barrier(MPI_COMM_WORLD);  // the campaign directory exists before any run starts
  std::vector<double> message(static_cast<std::size_t>(2 + n_responses));
  if (rank == 0) {
    report.runs = static_cast<int>(c.rows.size());
    report.skipped = c.skipped;
    report.results = c.results;
    std::size_t next = 0;
    for (int active = size - 1; active > 0;) {
      MPI_Status st;
      MPI_Recv(message.data(), static_cast<int>(message.size()), MPI_DOUBLE, MPI_ANY_SOURCE, tag_result, MPI_COMM_WORLD,
               &st);
      const int row = static_cast<int>(message[0]);
      if (row >= 0) {
        Row& r = c.rows[static_cast<std::size_t>(row)];
        r.status = message[1] != 0.0 ? "done" : "failed";
        r.responses.assign(message.begin() + 2, message.end());
        (r.status == "done" ? report.ran : report.failed) += 1;
        write_results(c);
        if (progress) {
          fmt::print(stderr, "run {} {} on rank {} ({} of {} done)\n", r.std_order, r.status, st.MPI_SOURCE,
                     report.skipped + report.ran, report.runs);
        }
      }
      int assign = -1;
      if (next < c.todo.size()) {
        assign = static_cast<int>(c.todo[next++]);
      } else {
        --active;
      }
      MPI_Send(&assign, 1, MPI_INT, st.MPI_SOURCE, tag_row, MPI_COMM_WORLD);
    }
  } else {
    report.coordinator = false;
    message[0] = -1.0;
    for (;;) {
      MPI_Send(message.data(), static_cast<int>(message.size()), MPI_DOUBLE, 0, tag_result, MPI_COMM_WORLD);
      int row = -1;
      MPI_Recv(&row, 1, MPI_INT, 0, tag_row, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      if (row < 0) break;
      const auto i = static_cast<std::size_t>(row);
      const pid_t pid = start_run(c, i);
      int status = 0;
      while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      finish_run(c, i, status);
      message[0] = row;
      message[1] = c.rows[i].status == "done" ? 1.0 : 0.0;
      for (int k = 0; k < n_responses; ++k) {
        message[static_cast<std::size_t>(2 + k)] =
            c.rows[i].status == "done" ? c.rows[i].responses[static_cast<std::size_t>(k)] : 0.0;
      }
    }
  }
  MPI_Finalize();
  return report;
}

}  // namespace bushel::doe::detail
