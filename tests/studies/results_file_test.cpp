#include "studies/results_file.h"

#include "core/error.h"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>

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
