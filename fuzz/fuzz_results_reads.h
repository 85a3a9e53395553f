// What the results_h5 harness reads from a fuzzed results file: every dataset and attribute its
// seed holds (make_fuzz_seeds), through one studies/results/results_file.h ResultsReader. Shared with the
// regression test, so a kept input is replayed exactly as it was fuzzed.
#pragma once

#include <filesystem>

namespace hipfai::fuzz {

// Makes every read in one child process (a file that crashes HDF5 there is refused:
// studies::DamagedHdf5File), even after one failed; then throws the first read's hipfai::Error, if any.
void read_results_file(const std::filesystem::path& file);

}  // namespace hipfai::fuzz
