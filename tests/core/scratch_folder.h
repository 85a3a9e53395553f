// Helpers of the core tests that write files: an empty folder per test, a file's bytes.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace hipfai::test {

// <build>/test-scratch/<suite>/<current test's name>, emptied.
inline std::filesystem::path scratch_folder(const std::string& suite) {
  const std::filesystem::path dir = std::filesystem::path(HIPFAI_BINARY_DIR) / "test-scratch" / suite /
                                    ::testing::UnitTest::GetInstance()->current_test_info()->name();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// The file's bytes ("" when it cannot be read).
inline std::string file_contents(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace hipfai::test
