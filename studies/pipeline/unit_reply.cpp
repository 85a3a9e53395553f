#include "studies/pipeline/unit_reply.h"

#include "core/error.h"

namespace hipfai::studies {

void UnitReplyReader::take(void* out, std::size_t size) {
  if (bytes_.size() - at_ < size) throw_error("a worker rank's reply is truncated");
  std::memcpy(out, bytes_.data() + at_, size);
  at_ += size;
}

void UnitReplyReader::size_check(std::uint64_t count, std::size_t bytes_each) const {
  if (count > (bytes_.size() - at_) / bytes_each) throw_error("a worker rank's reply is truncated");
}

std::size_t UnitReplyReader::size_of_next(std::size_t bytes_each) {
  const auto count = get<std::uint64_t>();
  size_check(count, bytes_each);
  return static_cast<std::size_t>(count);
}

void UnitReplyReader::expect_end() const {
  if (at_ != bytes_.size()) throw_error("a worker rank's reply has ", bytes_.size() - at_, " bytes too many");
}

}  // namespace hipfai::studies
