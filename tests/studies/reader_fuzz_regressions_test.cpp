// Inputs the fuzzer found in the study-level readers (scripts/fuzz; kept in
// tests/data/fuzz-regressions/<harness>/): each is replayed exactly as its harness fed it (the same
// entry point, the same folder of tissue meshes, the same reads) and must give a one-line
// hipfai::Error at once. The mesh readers' inputs: MeshIoFuzzRegressions (tests/geometry).
#include "core/error.h"
#include "fuzz_hip_folder.h"
#include "fuzz_results_reads.h"
#include "geometry/hip_model.h"
#include "studies/estimator_model_file.h"
#include "studies/pipeline/motion.h"
#include "studies/pipeline/scene.h"
#include "studies/pipeline/segmented_hip.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>

namespace hipfai::studies {
namespace {

namespace fs = std::filesystem;

std::string text_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Harness name -> how it feeds a kept input to its reader (fuzz/fuzz_<harness>.cpp).
const std::map<std::string, std::function<void(const fs::path&)>>& replays() {
  static const std::map<std::string, std::function<void(const fs::path&)>> table{
      {"scene", [](const fs::path& f) { (void)parse_scene(text_of(f), f); }},
      {"motion", [](const fs::path& f) { (void)parse_motion_csv(text_of(f), "fuzz.csv"); }},
      {"model_json",
       [](const fs::path& f) {
         (void)geometry::hip_model_from_json(text_of(f), fuzz::hip_folder());
       }},
      {"hip_json",
       [](const fs::path& f) { (void)segmented_hip_from_json(text_of(f), fuzz::hip_folder()); }},
      {"estimator_model", [](const fs::path& f) { (void)read_estimator_model(f); }},
      {"results_h5", [](const fs::path& f) { fuzz::read_results_file(f); }},
  };
  return table;
}

TEST(StudyReadersFuzzRegressions, EveryFoundInputIsAOneLineError) {
  const fs::path dir = fs::path(HIPFAI_SOURCE_DIR) / "tests/data/fuzz-regressions";
  int inputs = 0;
  for (const auto& [harness, replay] : replays()) {
    if (!fs::is_directory(dir / harness)) continue;
    for (const auto& entry : fs::directory_iterator(dir / harness)) {
      ++inputs;
      try {
        replay(entry.path());
        ADD_FAILURE() << entry.path() << ": read without an error";
      } catch (const Error& error) {
        EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos)
            << entry.path() << ": " << error.what();
      }
    }
  }
  EXPECT_GE(inputs, 1);
}

}  // namespace
}  // namespace hipfai::studies
