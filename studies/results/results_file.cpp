#include "studies/results/results_file.h"

#include "core/error.h"
#include "studies/results/hdf5_child.h"

#include <algorithm>
#include <hdf5.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <functional>
#include <stdexcept>

#include <limits>
#include <system_error>
#include <utility>

namespace hipfai::studies {

namespace {

// Silences HDF5's own error stack printing; failures are reported through hipfai::Error.
struct QuietHdf5 {
  QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }
};
const QuietHdf5 quiet_hdf5;

void check(herr_t status, const std::string& what) {
  if (status < 0) throw_error("HDF5: ", what, " failed");
}

hid_t check_id(hid_t id, const std::string& what) {
  if (id < 0) throw_error("HDF5: ", what, " failed");
  return id;
}

template <typename T>
void write_numeric(hid_t file, const std::string& path, const std::vector<T>& values,
                   std::size_t cols, hid_t mem_type, hid_t file_type) {
  if (cols == 0 || values.size() % cols != 0) {
    throw_error("HDF5: dataset ", path, ": ", values.size(), " values do not fill ", cols,
                " columns");
  }
  const hsize_t dims[2] = {values.size() / cols, cols};
  const hid_t space = check_id(H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr), path);
  const hid_t set = H5Dcreate2(file, path.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT,
                               H5P_DEFAULT);
  H5Sclose(space);
  check_id(set, "creating dataset " + path);
  const herr_t status =
      values.empty() ? 0 : H5Dwrite(set, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  H5Dclose(set);
  check(status, "writing dataset " + path);
}

void write_string_attribute(hid_t object, const std::string& name, const std::string& value) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.empty() ? 1 : value.size());
  H5Tset_strpad(type, H5T_STR_NULLTERM);
  const hid_t space = H5Screate(H5S_SCALAR);
  if (H5Aexists(object, name.c_str()) > 0) H5Adelete(object, name.c_str());
  const hid_t attribute = H5Acreate2(object, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  herr_t status = -1;
  if (attribute >= 0) {
    status = H5Awrite(attribute, type, value.c_str());
    H5Aclose(attribute);
  }
  H5Sclose(space);
  H5Tclose(type);
  check(status, "writing attribute " + name);
}

}  // namespace

ResultsFile::ResultsFile(std::filesystem::path path)
    : atomic_(std::move(path)) {
  if (atomic_.target().has_parent_path()) {
    std::error_code ignored;
    std::filesystem::create_directories(atomic_.target().parent_path(), ignored);
  }
  file_ = H5Fcreate(atomic_.partial_path().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file_ < 0) throw_error(atomic_.target().string(), ": cannot create HDF5 file");
}

// The HDF5 handle is closed here; atomic_, destroyed after this body, then removes the partial
// file unless commit() moved it into place.
ResultsFile::~ResultsFile() {
  if (file_ >= 0) H5Fclose(static_cast<hid_t>(file_));
}

void ResultsFile::ensure_parent_groups(const std::string& path) {
  for (std::size_t slash = path.find('/', 1); slash != std::string::npos;
       slash = path.find('/', slash + 1)) {
    create_group(path.substr(0, slash));
  }
}

void ResultsFile::create_group(const std::string& path) {
  if (path.empty() || path == "/") return;
  if (H5Lexists(file_, path.c_str(), H5P_DEFAULT) > 0) return;
  ensure_parent_groups(path);
  const hid_t group = check_id(
      H5Gcreate2(file_, path.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "group " + path);
  H5Gclose(group);
}

void ResultsFile::write(const std::string& path, const std::vector<double>& values,
                        std::size_t cols, const std::string& units) {
  ensure_parent_groups(path);
  write_numeric(file_, path, values, cols, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE);
  set_attribute(path, "units", units);
}

void ResultsFile::write_integers(const std::string& path, const std::vector<std::int64_t>& values,
                        std::size_t cols, const std::string& units) {
  ensure_parent_groups(path);
  write_numeric(file_, path, values, cols, H5T_NATIVE_INT64, H5T_STD_I64LE);
  set_attribute(path, "units", units);
}

void ResultsFile::write_strings(const std::string& path, const std::vector<std::string>& values) {
  ensure_parent_groups(path);
  std::vector<const char*> pointers;
  for (const auto& value : values) pointers.push_back(value.c_str());
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, H5T_VARIABLE);
  const hsize_t dims[1] = {values.size()};
  const hid_t space = H5Screate_simple(1, dims, nullptr);
  const hid_t set =
      H5Dcreate2(file_, path.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  herr_t status = -1;
  if (set >= 0) {
    status = values.empty() ? 0
                            : H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data());
    H5Dclose(set);
  }
  H5Sclose(space);
  H5Tclose(type);
  check(status, "writing strings " + path);
}

void ResultsFile::set_attribute(const std::string& object, const std::string& name,
                                const std::string& value) {
  const hid_t handle = check_id(H5Oopen(file_, object.c_str(), H5P_DEFAULT), "opening " + object);
  try {
    write_string_attribute(handle, name, value);
  } catch (...) {
    H5Oclose(handle);
    throw;
  }
  H5Oclose(handle);
}

void ResultsFile::set_attribute(const std::string& object, const std::string& name,
                                double value) {
  const hid_t handle = check_id(H5Oopen(file_, object.c_str(), H5P_DEFAULT), "opening " + object);
  const hid_t space = H5Screate(H5S_SCALAR);
  if (H5Aexists(handle, name.c_str()) > 0) H5Adelete(handle, name.c_str());
  const hid_t attribute =
      H5Acreate2(handle, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT);
  herr_t status = -1;
  if (attribute >= 0) {
    status = H5Awrite(attribute, H5T_NATIVE_DOUBLE, &value);
    H5Aclose(attribute);
  }
  H5Sclose(space);
  H5Oclose(handle);
  check(status, "writing attribute " + name);
}

void ResultsFile::commit() {
  if (committed_) return;
  H5Fclose(static_cast<hid_t>(file_));
  file_ = -1;
  atomic_.commit();
  committed_ = true;
}

namespace {

// The reads themselves, on a file open in the child process (read_in_child).
std::vector<double> dataset_of(hid_t handle, const std::filesystem::path& file, const std::string& path,
                               std::size_t* rows, std::size_t* cols) {
  const hid_t set = H5Dopen2(handle, path.c_str(), H5P_DEFAULT);
  if (set < 0) throw_error(file.string(), ": no dataset ", path);
  // Any rank: rows = the first extent, cols = the product of the others (a scalar is 1 x 1).
  const hid_t space = H5Dget_space(set);
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> extents(static_cast<std::size_t>(std::max(rank, 0)));
  if (rank < 0 || (rank > 0 && H5Sget_simple_extent_dims(space, extents.data(), nullptr) != rank)) {
    H5Sclose(space);
    H5Dclose(set);
    throw_error(file.string(), ": ", path, ": unreadable dataspace");
  }
  H5Sclose(space);
  hsize_t dims[2] = {1, 1};
  for (int d = 0; d < rank; ++d) dims[d == 0 ? 0 : 1] *= extents[static_cast<std::size_t>(d)];
  // The extents and the element type are only claims: a corrupt file may declare billions of
  // values, or values of gigabytes each, with nothing stored behind them (HDF5 would allocate
  // and fill them all). Numbers are integers or floats of at most 8 bytes; every stored value
  // takes at least a byte unless a filter (compression) packs it, and what is stored lies within
  // the file.
  const hid_t type = H5Dget_type(set);
  const H5T_class_t type_class = type < 0 ? H5T_NO_CLASS : H5Tget_class(type);
  const std::size_t type_size = type < 0 ? 0 : H5Tget_size(type);
  if (type >= 0) H5Tclose(type);
  std::error_code ec;
  const std::uintmax_t file_bytes = std::filesystem::file_size(file, ec);
  const hsize_t stored = H5Dget_storage_size(set);
  const hid_t create = H5Dget_create_plist(set);
  const int filters = create < 0 ? 0 : H5Pget_nfilters(create);
  if (create >= 0) H5Pclose(create);
  const bool overflow = dims[1] != 0 && dims[0] > std::numeric_limits<hsize_t>::max() / dims[1];
  const bool number = (type_class == H5T_INTEGER || type_class == H5T_FLOAT) && type_size >= 1 && type_size <= 8;
  if (!number || overflow || (filters == 0 && dims[0] * dims[1] > stored) || ec || stored > file_bytes) {
    H5Dclose(set);
    throw_error(file.string(), ": ", path, ": not numbers, or more values than the file stores (corrupt file)");
  }
  std::vector<double> values(dims[0] * dims[1]);
  const herr_t status = values.empty() ? 0
                                       : H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL,
                                                 H5P_DEFAULT, values.data());
  H5Dclose(set);
  check(status, "reading " + path);
  if (rows) *rows = dims[0];
  if (cols) *cols = dims[1];
  return values;
}

std::string string_attribute_of(hid_t handle, const std::filesystem::path& file, const std::string& object,
                                const std::string& name) {
  const hid_t attribute = H5Aopen_by_name(handle, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
  if (attribute < 0) {
    throw_error(file.string(), ": no attribute ", name, " on ", object);
  }
  // One fixed-length string: H5Aread writes every element of the attribute, so an array of
  // strings (or a variable-length one, whose elements are pointers) would overrun `value`.
  const hid_t space = H5Aget_space(attribute);
  const hssize_t points = space < 0 ? -1 : H5Sget_simple_extent_npoints(space);
  if (space >= 0) H5Sclose(space);
  const hid_t type = H5Aget_type(attribute);
  if (points != 1 || type < 0 || H5Tget_class(type) != H5T_STRING || H5Tis_variable_str(type) != 0) {
    if (type >= 0) H5Tclose(type);
    H5Aclose(attribute);
    throw_error(file.string(), ": attribute ", name, " on ", object, " is not one fixed-length string");
  }
  std::string value(H5Tget_size(type), '\0');
  const hid_t memory = H5Tcopy(H5T_C_S1);
  H5Tset_size(memory, value.size());
  const herr_t status = H5Aread(attribute, memory, value.data());
  H5Tclose(memory);
  H5Tclose(type);
  H5Aclose(attribute);
  check(status, "reading attribute " + name);
  while (!value.empty() && value.back() == '\0') value.pop_back();
  return value;
}

// The child's answer, item after item: a tag byte, then a dataset's rows, cols and values, an
// attribute's text, or an error's message (each length-prefixed).
enum class Tag : char { kDataset = 'D', kAttribute = 'A', kError = 'E' };

void put_bytes(std::string& out, const void* data, std::size_t size) {
  out.append(static_cast<const char*>(data), size);
}
void put_u64(std::string& out, std::uint64_t value) { put_bytes(out, &value, sizeof value); }
void put_text(std::string& out, const std::string& text) {
  put_u64(out, text.size());
  out += text;
}

void write_all(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t wrote = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (wrote < 0 && errno == EINTR) continue;
    if (wrote <= 0) throw std::runtime_error("pipe");
    done += static_cast<std::size_t>(wrote);
  }
}

class AnswerReader {
 public:
  AnswerReader(const std::string& bytes, const std::filesystem::path& file) : bytes_(bytes), file_(file) {}
  bool done() const { return at_ == bytes_.size(); }
  char tag() { return static_cast<char>(take(1)[0]); }
  std::uint64_t u64() {
    std::uint64_t value = 0;
    std::memcpy(&value, take(sizeof value), sizeof value);
    return value;
  }
  std::string text() {
    const std::uint64_t size = u64();
    return std::string(take(size), static_cast<std::size_t>(size));
  }
  std::vector<double> doubles(std::uint64_t count) {
    if (count > (bytes_.size() - at_) / sizeof(double)) truncated();
    std::vector<double> values(static_cast<std::size_t>(count));
    if (count > 0) std::memcpy(values.data(), take(count * sizeof(double)), values.size() * sizeof(double));
    return values;
  }

 private:
  const char* take(std::uint64_t size) {
    if (size > bytes_.size() - at_) truncated();
    const char* data = bytes_.data() + at_;
    at_ += static_cast<std::size_t>(size);
    return data;
  }
  [[noreturn]] void truncated() const {
    throw_error(file_.string(), ": the HDF5 reading process answered with a truncated message");
  }
  const std::string& bytes_;
  const std::filesystem::path& file_;
  std::size_t at_ = 0;
};

}  // namespace

ResultsReader::ResultsReader(std::filesystem::path file) : file_(std::move(file)) {}

ResultsReader::~ResultsReader() = default;

void ResultsReader::prefetch(const std::vector<std::string>& datasets,
                             const std::vector<std::pair<std::string, std::string>>& attributes) {
  const std::filesystem::path file = file_;
  const std::string answer = run_hdf5_in_child(file, [&](int fd) {
    std::string out;
    const hid_t handle = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    // Each read answers its values or its error (what the reader throws in this process).
    const auto item = [&](const std::function<void()>& read) {
      try {
        if (handle < 0) throw_error(file.string(), ": cannot open HDF5 file");
        read();
      } catch (const Error& error) {
        out += static_cast<char>(Tag::kError);
        put_text(out, error.what());
      }
    };
    for (const std::string& path : datasets) {
      item([&] {
        std::size_t rows = 0, cols = 0;
        const std::vector<double> values = dataset_of(handle, file, path, &rows, &cols);
        out += static_cast<char>(Tag::kDataset);
        put_u64(out, rows);
        put_u64(out, cols);
        put_bytes(out, values.data(), values.size() * sizeof(double));
      });
    }
    for (const auto& attribute : attributes) {
      item([&] {
        const std::string value = string_attribute_of(handle, file, attribute.first, attribute.second);
        out += static_cast<char>(Tag::kAttribute);
        put_text(out, value);
      });
    }
    if (handle >= 0) H5Fclose(handle);
    write_all(fd, out);
  });
  AnswerReader in(answer, file_);
  const auto entry = [&](Tag expected) {
    Entry result;
    const char tag = in.tag();
    if (tag == static_cast<char>(Tag::kError)) {
      result.error = in.text();
    } else if (tag != static_cast<char>(expected)) {
      throw_error(file_.string(), ": the HDF5 reading process answered out of order");
    } else if (expected == Tag::kDataset) {
      result.rows = in.u64();
      result.cols = in.u64();
      if (result.cols != 0 && result.rows > std::numeric_limits<std::uint64_t>::max() / result.cols) {
        throw_error(file_.string(), ": the HDF5 reading process answered with a bad shape");
      }
      result.values = in.doubles(result.rows * result.cols);
    } else {
      result.text = in.text();
    }
    return result;
  };
  for (const std::string& path : datasets) datasets_[path] = entry(Tag::kDataset);
  for (const auto& key : attributes) attributes_[key] = entry(Tag::kAttribute);
  if (!in.done()) throw_error(file_.string(), ": the HDF5 reading process answered more than asked");
}

std::vector<double> ResultsReader::dataset(const std::string& path, std::size_t* rows, std::size_t* cols) {
  if (datasets_.count(path) == 0) prefetch({path}, {});
  const Entry& entry = datasets_.at(path);
  if (!entry.error.empty()) throw Error(entry.error);
  if (rows) *rows = static_cast<std::size_t>(entry.rows);
  if (cols) *cols = static_cast<std::size_t>(entry.cols);
  return entry.values;
}

std::string ResultsReader::string_attribute(const std::string& object, const std::string& name) {
  const std::pair<std::string, std::string> key{object, name};
  if (attributes_.count(key) == 0) prefetch({}, {key});
  const Entry& entry = attributes_.at(key);
  if (!entry.error.empty()) throw Error(entry.error);
  return entry.text;
}

std::vector<double> read_dataset(const std::filesystem::path& file, const std::string& path,
                                 std::size_t* rows, std::size_t* cols) {
  return ResultsReader(file).dataset(path, rows, cols);
}

std::string read_string_attribute(const std::filesystem::path& file, const std::string& object,
                                  const std::string& name) {
  return ResultsReader(file).string_attribute(object, name);
}

}  // namespace hipfai::studies
