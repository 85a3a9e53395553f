#include "studies/results/results_file.h"

#include "core/error.h"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>
#include <vector>

namespace hipfai::studies {
namespace {

std::filesystem::path temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("hipfai_" + name);
}

TEST(ResultsFile, RoundTripsDatasetsAndAttributes) {
  const auto path = temp_path("roundtrip.h5");
  std::filesystem::remove(path);
  {
    ResultsFile file(path);
    file.write("/models/a/depth", {1.5, 2.5, 3.5, 4.5}, 2, "mm");
    file.set_attribute("/", "code_version", "test");
    file.commit();
  }
  std::size_t rows = 0, cols = 0;
  const auto values = read_dataset(path, "/models/a/depth", &rows, &cols);
  EXPECT_EQ(rows, 2u);
  EXPECT_EQ(cols, 2u);
  EXPECT_DOUBLE_EQ(values[3], 4.5);
  EXPECT_EQ(read_string_attribute(path, "/models/a/depth", "units"), "mm");
  EXPECT_EQ(read_string_attribute(path, "/", "code_version"), "test");
}

TEST(ResultsFile, UncommittedFileLeavesNothingBehind) {
  const auto path = temp_path("uncommitted.h5");
  std::filesystem::remove(path);
  {
    ResultsFile file(path);
    file.write("/x", {1.0}, 1, "mm");
  }
  EXPECT_FALSE(std::filesystem::exists(path));
  // Its temporary, "<name>.<pid>-<n>.partial", is gone too (other files of /tmp are not ours).
  for (const auto& entry : std::filesystem::directory_iterator(path.parent_path())) {
    EXPECT_NE(entry.path().filename().string().rfind(path.filename().string() + ".", 0), 0u) << entry.path();
  }
}

// An attribute of three strings (a foreign file's): reading it as one string must be refused,
// not read into a one-string buffer (H5Aread writes all three).
// A compressed dataset stores fewer bytes than it has values (here 4096 zeros in a few dozen
// bytes): the bound on stored bytes that rejects corrupt size claims must not reject it.
TEST(ResultsFile, CompressedDatasetSmallerThanItsValuesIsRead) {
  const auto path = temp_path("compressed.h5");
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hsize_t count = 4096;
  const hid_t space = H5Screate_simple(1, &count, nullptr);
  const hid_t create = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_chunk(create, 1, &count);
  H5Pset_deflate(create, 9);
  const hid_t set = H5Dcreate2(file, "zeros", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, create, H5P_DEFAULT);
  const std::vector<double> zeros(count, 0.0);
  ASSERT_GE(H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, zeros.data()), 0);
  ASSERT_LT(H5Dget_storage_size(set), count);
  H5Dclose(set);
  H5Pclose(create);
  H5Sclose(space);
  H5Fclose(file);
  const auto values = read_dataset(path, "/zeros");
  EXPECT_EQ(values, zeros);
  std::filesystem::remove(path);
}

TEST(ResultsFile, StringAttributeOfSeveralStringsIsAnError) {
  const auto path = temp_path("string_array_attribute.h5");
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, 4);
  const hsize_t count = 3;
  const hid_t space = H5Screate_simple(1, &count, nullptr);
  const hid_t attribute = H5Acreate2(file, "format", type, space, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(H5Awrite(attribute, type, "abcdefghijkl"), 0);
  H5Aclose(attribute);
  H5Sclose(space);
  H5Tclose(type);
  H5Fclose(file);
  try {
    (void)read_string_attribute(path, "/", "format");
    ADD_FAILURE() << "an attribute of three strings was read as one";
  } catch (const hipfai::Error& error) {
    EXPECT_NE(std::string(error.what()).find("not one fixed-length string"), std::string::npos) << error.what();
  }
  std::filesystem::remove(path);
}

TEST(ResultsFile, RaggedDatasetIsAnError) {
  ResultsFile file(temp_path("ragged.h5"));
  EXPECT_THROW(file.write("/x", {1.0, 2.0, 3.0}, 2, "mm"), hipfai::Error);
}

}  // namespace
}  // namespace hipfai::studies
