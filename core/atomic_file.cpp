#include "core/atomic_file.h"

#include "core/error.h"

#include <fstream>
#include <system_error>

namespace hipfai {

void write_file_atomically(const std::filesystem::path& path, const std::string& text) {
  const std::filesystem::path partial = path.string() + ".partial";
  {
    std::ofstream out(partial, std::ios::binary);
    if (!out) throw_error(partial.string(), ": cannot open for writing");
    out << text;
    out.flush();
    if (!out) throw_error(partial.string(), ": write failed");
  }
  std::error_code error;
  std::filesystem::rename(partial, path, error);
  if (error) throw_error(path.string(), ": cannot rename into place: ", error.message());
}

}  // namespace hipfai
