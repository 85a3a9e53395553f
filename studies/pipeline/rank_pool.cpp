#include "studies/pipeline/rank_pool.h"

#ifdef HIPFAI_WITH_FEM

#include <algorithm>
#include <chrono>
#include <exception>
#include <thread>
#include <vector>

namespace hipfai::studies {
namespace {

enum Tag : int {
  kUnitTag = 1,    // rank 0 -> worker: one unsigned long long, the unit's index
  kStopTag = 2,    // rank 0 -> worker: no more units (empty)
  kReplyTag = 3,   // worker -> rank 0: the unit's index, then its reply bytes
  kFailedTag = 4,  // worker -> rank 0: the unit's index, then the error message
};

// Short enough not to matter against units of seconds, long enough to leave the cores alone.
constexpr std::chrono::milliseconds kPollInterval{5};

// Waits for a message from `source` (or any) without MPI's busy polling; returns its status.
MPI_Status wait_for_message(MPI_Comm comm, int source) {
  for (;;) {
    int arrived = 0;
    MPI_Status status;
    MPI_Iprobe(source, MPI_ANY_TAG, comm, &arrived, &status);
    if (arrived) return status;
    std::this_thread::sleep_for(kPollInterval);
  }
}

// A reply's bytes: the unit's index (8 bytes, this machine's order: every rank runs the same
// build) then the payload.
std::string frame(std::size_t unit, const std::string& payload) {
  const unsigned long long index = unit;
  std::string bytes(reinterpret_cast<const char*>(&index), sizeof index);
  return bytes + payload;
}

void send_stop_to_all(MPI_Comm comm, int size) {
  for (int rank = 1; rank < size; ++rank) MPI_Send(nullptr, 0, MPI_CHAR, rank, kStopTag, comm);
}

}  // namespace

void run_rank_pool_master(MPI_Comm comm, const RankPoolMaster& master) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  std::vector<int> free_ranks;
  for (int rank = size - 1; rank >= 1; --rank) free_ranks.push_back(rank);
  int running = 0;
  try {
    for (;;) {
      while (!free_ranks.empty()) {
        const std::optional<std::size_t> unit = master.next_unit();
        if (!unit) break;
        const unsigned long long index = *unit;
        MPI_Send(&index, 1, MPI_UNSIGNED_LONG_LONG, free_ranks.back(), kUnitTag, comm);
        free_ranks.pop_back();
        ++running;
      }
      if (running == 0) break;  // nothing runs and nothing is ready: done
      const MPI_Status status = wait_for_message(comm, MPI_ANY_SOURCE);
      int count = 0;
      MPI_Get_count(&status, MPI_CHAR, &count);
      std::string bytes(static_cast<std::size_t>(count), '\0');
      MPI_Recv(bytes.data(), count, MPI_CHAR, status.MPI_SOURCE, status.MPI_TAG, comm, MPI_STATUS_IGNORE);
      --running;
      free_ranks.push_back(status.MPI_SOURCE);
      unsigned long long index = 0;
      if (bytes.size() < sizeof index) continue;  // not ours: cannot happen with this protocol
      std::copy_n(bytes.data(), sizeof index, reinterpret_cast<char*>(&index));
      UnitOutcome outcome;
      outcome.ok = status.MPI_TAG == kReplyTag;
      (outcome.ok ? outcome.reply : outcome.error) = bytes.substr(sizeof index);
      master.finished(static_cast<std::size_t>(index), status.MPI_SOURCE, outcome);
    }
  } catch (...) {
    // Workers still running send their reply first (small: sent eagerly), then take the stop.
    send_stop_to_all(comm, size);
    throw;
  }
  send_stop_to_all(comm, size);
}

void run_rank_pool_worker(MPI_Comm comm, const std::function<std::string(std::size_t unit)>& run) {
  for (;;) {
    const MPI_Status status = wait_for_message(comm, 0);
    if (status.MPI_TAG == kStopTag) {
      MPI_Recv(nullptr, 0, MPI_CHAR, 0, kStopTag, comm, MPI_STATUS_IGNORE);
      return;
    }
    unsigned long long index = 0;
    MPI_Recv(&index, 1, MPI_UNSIGNED_LONG_LONG, 0, kUnitTag, comm, MPI_STATUS_IGNORE);
    std::string bytes;
    int tag = kReplyTag;
    try {
      bytes = frame(static_cast<std::size_t>(index), run(static_cast<std::size_t>(index)));
    } catch (const std::exception& e) {
      bytes = frame(static_cast<std::size_t>(index), e.what());
      tag = kFailedTag;
    } catch (...) {
      bytes = frame(static_cast<std::size_t>(index), "unknown failure");
      tag = kFailedTag;
    }
    MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_CHAR, 0, tag, comm);
  }
}

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
