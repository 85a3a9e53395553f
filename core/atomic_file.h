// hipfai — whole files written atomically: the text goes to "<path>.partial", which is renamed
// over `path` only when completely written, so an interrupted run never leaves a half file.
#pragma once

#include <filesystem>
#include <string>

namespace hipfai {

// Throws hipfai::Error naming the file when it cannot be written or renamed into place.
void write_file_atomically(const std::filesystem::path& path, const std::string& text);

}  // namespace hipfai
