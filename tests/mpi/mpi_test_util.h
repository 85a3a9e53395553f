// Helpers of the tests run under mpirun (tests/mpi/): files compared without their timing
// columns, a barrier the waiting ranks sleep through, and the one-process run of a study on rank 0.
#pragma once

#include "studies/pipeline/mpi_launch.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <chrono>
#include <exception>
#include <filesystem>
#include <functional>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace hipfai::studies::mpi_test {

inline std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A timing column: its name ends in _s, _ms or _seconds, or has _ms_ (penetration_ms_per_step).
inline bool is_timing_column(const std::string& name) {
  return name.ends_with("_s") || name.ends_with("_ms") || name.ends_with("_seconds") ||
         name.find("_ms_") != std::string::npos;
}

// A CSV without its timing columns.
inline std::string without_timings(const std::filesystem::path& file) {
  std::istringstream lines(read_text(file));
  std::string line, out;
  std::vector<bool> keep;
  while (std::getline(lines, line)) {
    std::istringstream cells(line);
    std::string cell;
    std::size_t c = 0;
    std::string row;
    while (std::getline(cells, cell, ',')) {
      if (keep.size() <= c) keep.push_back(!is_timing_column(cell));
      if (keep[c]) row += cell + ',';
      ++c;
    }
    out += row + '\n';
  }
  return out;
}

inline void wait_sleeping(MPI_Request& request) {
  for (int done = 0; !done;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

// A barrier the waiting ranks sleep through (MPI_Barrier would spin them on the cores rank 0
// computes on).
inline void sleeping_barrier() {
  MPI_Request request;
  MPI_Ibarrier(MPI_COMM_WORLD, &request);
  wait_sleeping(request);
}

// A sleeping barrier that tells every rank whether all were `ok` (so that a rank that failed
// before a collective study does not leave the others waiting in it).
inline bool every_rank_ok(bool ok) {
  int mine = ok ? 1 : 0, all = 0;
  MPI_Request request;
  MPI_Iallreduce(&mine, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD, &request);
  wait_sleeping(request);
  return all == 1;
}

// The scratch folder of a study's test in the build tree.
inline std::filesystem::path scratch(const std::string& study) {
  return std::filesystem::path(HIPFAI_BINARY_DIR) / "test-scratch" / study;
}

// Rank 0 clears the study's scratch folder and runs it in one process, while the others wait;
// false on every rank when it failed (the failure is rank 0's).
inline bool serial_run_on_rank_zero(const std::string& study, const std::function<void()>& serial) {
  bool ok = true;
  if (join_mpi_world().rank == 0) {
    std::filesystem::remove_all(scratch(study));
    try {
      serial();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "the one-process run: " << e.what();
    }
    ok = !::testing::Test::HasFailure();
  }
  return every_rank_ok(ok);
}

}  // namespace hipfai::studies::mpi_test
