// hipfai — a unit's reply as bytes, to cross the ranks of an MPI job (studies/pipeline/rank_pool.h)
// and come back as the same typed value. Numbers as they are in memory (every rank runs the same
// build on the same kind of machine, so a double comes back bit for bit); strings, vectors, maps
// and Eigen matrices with their sizes first. A study's own types take part through two functions
// found by argument-dependent lookup beside the type:
//   void write_reply(UnitReplyWriter& out, const T& value);
//   void read_reply(UnitReplyReader& in, T& value);
// which add / read the type's fields in one order.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace hipfai::studies {

class UnitReplyWriter {
 public:
  template <typename T>
  UnitReplyWriter& add(const T& value) {
    if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
      bytes_.append(reinterpret_cast<const char*>(&value), sizeof value);
    } else {
      write_reply(*this, value);
    }
    return *this;
  }
  UnitReplyWriter& add(const std::string& text) {
    add(static_cast<std::uint64_t>(text.size()));
    bytes_ += text;
    return *this;
  }
  template <typename T>
  UnitReplyWriter& add(const std::vector<T>& values) {
    add(static_cast<std::uint64_t>(values.size()));
    for (const T& v : values) add(v);
    return *this;
  }
  template <typename K, typename V>
  UnitReplyWriter& add(const std::map<K, V>& values) {
    add(static_cast<std::uint64_t>(values.size()));
    for (const auto& [key, value] : values) add(key).add(value);
    return *this;
  }
  template <typename A, typename B>
  UnitReplyWriter& add(const std::pair<A, B>& value) {
    return add(value.first).add(value.second);
  }
  template <int Rows, int Cols, int Options, int MaxRows, int MaxCols>
  UnitReplyWriter& add(const Eigen::Matrix<double, Rows, Cols, Options, MaxRows, MaxCols>& matrix) {
    add(static_cast<std::int64_t>(matrix.rows())).add(static_cast<std::int64_t>(matrix.cols()));
    for (Eigen::Index c = 0; c < matrix.cols(); ++c) {
      for (Eigen::Index r = 0; r < matrix.rows(); ++r) add(matrix(r, c));
    }
    return *this;
  }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

class UnitReplyReader {
 public:
  explicit UnitReplyReader(const std::string& bytes) : bytes_(bytes) {}

  template <typename T>
  UnitReplyReader& read(T& value) {
    if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
      take(&value, sizeof value);
    } else {
      read_reply(*this, value);
    }
    return *this;
  }
  UnitReplyReader& read(std::string& text) {
    text.assign(size_of_next(1), '\0');
    take(text.data(), text.size());
    return *this;
  }
  template <typename T>
  UnitReplyReader& read(std::vector<T>& values) {
    values.assign(size_of_next(1), T{});
    for (T& v : values) read(v);
    return *this;
  }
  template <typename K, typename V>
  UnitReplyReader& read(std::map<K, V>& values) {
    values.clear();
    for (std::size_t n = size_of_next(1); n > 0; --n) {
      K key{};
      read(key);
      read(values[key]);
    }
    return *this;
  }
  template <typename A, typename B>
  UnitReplyReader& read(std::pair<A, B>& value) {
    return read(value.first).read(value.second);
  }
  template <int Rows, int Cols, int Options, int MaxRows, int MaxCols>
  UnitReplyReader& read(Eigen::Matrix<double, Rows, Cols, Options, MaxRows, MaxCols>& matrix) {
    const auto rows = get<std::int64_t>(), cols = get<std::int64_t>();
    size_check(static_cast<std::uint64_t>(rows) * static_cast<std::uint64_t>(cols), sizeof(double));
    matrix.resize(rows, cols);
    for (Eigen::Index c = 0; c < matrix.cols(); ++c) {
      for (Eigen::Index r = 0; r < matrix.rows(); ++r) read(matrix(r, c));
    }
    return *this;
  }
  template <typename T>
  T get() {
    T value{};
    read(value);
    return value;
  }
  // Throws hipfai::Error unless every byte was read.
  void expect_end() const;

 private:
  void take(void* out, std::size_t size);
  // The element count that comes next, checked against the bytes left (elements of at least
  // `bytes_each` bytes).
  std::size_t size_of_next(std::size_t bytes_each);
  void size_check(std::uint64_t count, std::size_t bytes_each) const;

  const std::string& bytes_;
  std::size_t at_ = 0;
};

// A value as its reply bytes, and back (throws hipfai::Error on bytes that do not hold one).
template <typename T>
std::string encode_unit_reply(const T& value) {
  return UnitReplyWriter().add(value).take();
}
template <typename T>
T decode_unit_reply(const std::string& bytes) {
  UnitReplyReader in(bytes);
  T value = in.get<T>();
  in.expect_end();
  return value;
}

}  // namespace hipfai::studies
