#include "fem/rank_team.h"

#include "core/error.h"

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
