// A per-process scratch folder for the harnesses of readers that take a path: the fuzzed bytes are
// written to a file there (in /dev/shm when it exists, so no disk is involved) and the reader is
// given its path. The folder is removed when the process exits normally.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace hipfai::fuzz {

// <shm or temp>/hipfai-fuzz-<pid>, created on first use.
const std::filesystem::path& scratch_dir();

// Writes `bytes` to scratch_dir()/name (replacing it) and returns its path.
std::filesystem::path write_scratch_file(const std::string& name, std::string_view bytes);

}  // namespace hipfai::fuzz
