#include "fem/rank_team.h"

#include "core/error.h"

#include <sched.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <thread>

namespace hipfai::fem {

void wait_without_spinning(MPI_Request& request) {
  auto pause = std::chrono::microseconds(20);
  for (int done = 0;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return;
    std::this_thread::sleep_for(pause);
    pause = std::min<std::chrono::microseconds>(2 * pause, std::chrono::milliseconds(1));
  }
}

namespace {

// The header of a message: its kind and the payload's size in bytes.
struct Header {
  int message = 0;
  unsigned long long bytes = 0;
};

// A payload of any size, in pieces MPI's int counts can hold.
// (MPI_Bcast reads the root's buffer and writes the others'.)
void broadcast_bytes(char* bytes, std::size_t size, MPI_Comm communicator) {
  constexpr std::size_t kPiece = std::size_t{1} << 30;
  for (std::size_t first = 0; first < size; first += kPiece) {
    const std::size_t n = std::min(kPiece, size - first);
    MPI_Bcast(bytes + first, static_cast<int>(n), MPI_BYTE, 0, communicator);
  }
}

}  // namespace

RankTeam::RankTeam(MPI_Comm communicator) : communicator_(communicator) {
  MPI_Comm_rank(communicator_, &rank_);
  MPI_Comm_size(communicator_, &size_);
  if (size_ == 1) return;
  // Is the leader on this rank's node? Then its affinity says which of the node's CPUs it may
  // share with the leader.
  MPI_Comm node;
  MPI_Comm_split_type(communicator_, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
  MPI_Group team_group, node_group;
  MPI_Comm_group(communicator_, &team_group);
  MPI_Comm_group(node, &node_group);
  const int leader = 0;
  int leader_in_node = MPI_UNDEFINED;
  MPI_Group_translate_ranks(team_group, 1, &leader, node_group, &leader_in_node);
  MPI_Group_free(&team_group);
  MPI_Group_free(&node_group);
  MPI_Comm_free(&node);
  cpu_set_t cpus;
  CPU_ZERO(&cpus);
  if (sched_getaffinity(0, sizeof(cpus), &cpus) != 0) {
    for (int c = 0; c < CPU_SETSIZE; ++c) CPU_SET(c, &cpus);  // unknown: any CPU
  }
  struct Placement {
    int with_leader = 0;
    cpu_set_t cpus;
  } mine{leader_in_node != MPI_UNDEFINED ? 1 : 0, cpus};
  std::vector<Placement> all(rank_ == 0 ? static_cast<std::size_t>(size_) : 0);
  MPI_Gather(&mine, sizeof(Placement), MPI_BYTE, all.data(), sizeof(Placement), MPI_BYTE, 0,
             communicator_);
  if (rank_ != 0) return;
  leader_cpus_ = std::max(1, CPU_COUNT(&cpus));
  shares_leader_cpus_.assign(static_cast<std::size_t>(size_), false);
  for (std::size_t r = 1; r < all.size(); ++r) {
    cpu_set_t both;
    CPU_AND(&both, &all[r].cpus, &cpus);
    shares_leader_cpus_[r] = all[r].with_leader && CPU_COUNT(&both) > 0;
  }
}

std::vector<RankTeam::HelperCore> RankTeam::helper_cores(
    std::optional<double> leader_search_seconds) const {
  const bool searching = !leader_search_seconds || *leader_search_seconds > 0.0;
  // The leader's CPUs besides its solving thread's; with the searches, the last of them is
  // shared with their work.
  const int spare = leader_cpus_ - 1;
  const int free = searching ? spare - 1 : spare;
  int shared = 0;
  std::vector<HelperCore> out;
  for (std::size_t r = 1; r < shares_leader_cpus_.size(); ++r) {
    HelperCore core;
    if (!shares_leader_cpus_[r]) {
      core.has_core = true;
    } else if (shared < free) {
      core.has_core = true;
      ++shared;
    } else if (shared == free && searching && spare > 0) {
      core.has_core = leader_search_seconds.has_value();
      core.busy_seconds = leader_search_seconds.value_or(0.0);
      ++shared;
    }
    out.push_back(core);
  }
  return out;
}

void RankTeam::send(Message message, const std::vector<char>& payload) const {
  Header header{static_cast<int>(message), payload.size()};
  MPI_Request request;
  MPI_Ibcast(&header, sizeof(Header), MPI_BYTE, 0, communicator_, &request);
  wait_without_spinning(request);
  broadcast_bytes(const_cast<char*>(payload.data()), payload.size(), communicator_);
}

RankTeam::Message RankTeam::receive(std::vector<char>& payload) const {
  Header header;
  MPI_Request request;
  MPI_Ibcast(&header, sizeof(Header), MPI_BYTE, 0, communicator_, &request);
  wait_without_spinning(request);
  payload.assign(header.bytes, 0);
  broadcast_bytes(payload.data(), payload.size(), communicator_);
  return static_cast<Message>(header.message);
}

const char* ByteReader::take(std::size_t n) {
  if (n > bytes_.size() - position_) throw_error("fem: a message from rank 0 ended early");
  const char* data = bytes_.data() + position_;
  position_ += n;
  return data;
}

}  // namespace hipfai::fem
