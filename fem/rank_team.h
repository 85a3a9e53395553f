// hipfai — the ranks of one substructured FE run as a team: rank 0 leads, the others help it
// with the compliance columns.
//
// The substructured solver's long serial part is the compliance columns' MUMPS solves
// (fem/body_compliance.h); the rest of a run (contact search, condensed active sets, recovery,
// stresses) is short and threaded. So rank 0 solves the run with the threads a one-rank run has,
// and the other ranks help it with column blocks (BodyCompliance::share_column_blocks), each
// with its own copy of the bodies' factors, on a mesh of its own set up only in a run where it
// is given blocks (so a helper given none does no work). Replicating the rest on every rank would give each
// rank only its share of the machine's threads when the ranks share a machine (2 ranks on 2
// cores: one each, and no thread for the searches ahead), which costs more than the columns save.
//
// When helpers take blocks (TeamColumns, fem/contact_problem.h): with kSpareCores, rank 0 deals
// blocks to a helper only on a core of its own (helper_cores: on another node, on cores rank 0
// may not use, or on a core of rank 0's that its threads leave free, counting the work its
// searches ahead have left on it), and only as many as end with rank 0's, the helper's own
// factorisation counted (fem/column_deal.h); a helper factorises only when first given blocks, in a run where rank 0
// factorises every body (so that its factors are in rank 0's frames). On a node whose cores rank 0's threads already keep busy, a helper would only
// move work from one core's thread to another. With kEveryRank every set of columns is shared
// evenly.
//
// What flows: before a deal rank 0 sends the helpers the missing nodes and the deal (kColumns);
// after the run it sends what the callers of ContactProblem read on every rank (kRunDone: the
// result and the fields, fem/run_state_bytes.h), or the reason it failed (kRunFailed). A helper
// waits for these messages asleep (wait_without_spinning), so it leaves its core to rank 0's
// threads: Open MPI's blocking calls poll without sleeping.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <cstring>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace hipfai::fem {

// Waits for `request` with short sleeps between tests (20 us growing to 1 ms), so that a waiting
// rank leaves its core to the ranks and threads that compute.
void wait_without_spinning(MPI_Request& request);

class RankTeam {
 public:
  enum class Message : int {
    kColumns,    // payload: the missing nodes, the first block dealt and the deal (fem/column_deal.h)
    kRunDone,    // payload: the run's result and fields (fem/run_state_bytes.h)
    kRunFailed,  // payload: the leader's error message
  };

  explicit RankTeam(MPI_Comm communicator);

  // True on rank 0, which solves the run; the other ranks are its helpers.
  bool leads() const { return rank_ == 0; }
  // More than one rank: the leader has helpers to send to.
  bool has_helpers() const { return size_ > 1; }
  int size() const { return size_; }
  int rank() const { return rank_; }

  // Leader: per helper (ranks 1, 2, ...), the core it would solve columns on. Helpers on other
  // nodes, or whose CPUs (their affinity) do not overlap the leader's, have one of their own.
  // Helpers whose CPUs overlap the leader's share the leader's CPUs but the one its solving
  // thread takes, in rank order; while the leader's searches ahead have work left
  // (`leader_search_seconds` > 0, ContactSearchAhead::remaining_seconds), one of those CPUs is
  // theirs, and the helper given that one has that much work on it before its own (busy_seconds;
  // no core at all while the searches' work is not known yet).
  struct HelperCore {
    bool has_core = false;
    double busy_seconds = 0.0;
  };
  std::vector<HelperCore> helper_cores(std::optional<double> leader_search_seconds) const;

  // Leader: sends every helper the next message and its payload (collective with receive()).
  void send(Message message, const std::vector<char>& payload) const;
  // Helper: waits, asleep, for the leader's next message; its payload into `payload`.
  Message receive(std::vector<char>& payload) const;

 private:
  MPI_Comm communicator_;
  int rank_ = 0;
  int size_ = 1;
  // Leader: the CPUs it may run on, and per rank whether that rank may run on any of them
  // (on the leader's node, with an overlapping affinity).
  int leader_cpus_ = 1;
  std::vector<bool> shares_leader_cpus_;
};

// Values to bytes and back, for the leader's messages: trivially copyable values, arrays and
// vectors of them, in the order written. Both ends run the same build (docs/cluster.md). Both
// classes have the same io() calls, so one function template can list a structure's fields for
// writing and reading alike (fem/run_state_bytes.cpp).
class ByteWriter {
 public:
  template <class T>
  void io(const T& value) {
    io_array(&value, 1);
  }
  template <class T>
  void io(const std::vector<T>& values) {
    const std::size_t n = values.size();
    io(n);
    io_array(values.data(), n);
  }
  template <class T>
  void io_array(const T* values, std::size_t n) {
    static_assert(std::is_trivially_copyable_v<T>);
    const char* data = reinterpret_cast<const char*>(values);
    bytes_.insert(bytes_.end(), data, data + n * sizeof(T));
  }
  const std::vector<char>& bytes() const { return bytes_; }

 private:
  std::vector<char> bytes_;
};

class ByteReader {
 public:
  explicit ByteReader(const std::vector<char>& bytes) : bytes_(bytes) {}
  template <class T>
  void io(T& value) {
    io_array(&value, 1);
  }
  template <class T>
  void io(std::vector<T>& values) {
    std::size_t n = 0;
    io(n);
    values.resize(n);
    io_array(values.data(), n);
  }
  template <class T>
  void io_array(T* values, std::size_t n) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (n > 0) std::memcpy(values, take(n * sizeof(T)), n * sizeof(T));
  }

 private:
  // The next n bytes; throws hipfai::Error past the end.
  const char* take(std::size_t n);

  const std::vector<char>& bytes_;
  std::size_t position_ = 0;
};

}  // namespace hipfai::fem
