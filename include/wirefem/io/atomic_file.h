// Writing a whole small file (a run's summary.json) next to its final name
// and renaming it, so a reader never sees it half written and an
// interruption leaves the previous version in place.
#pragma once

#include <filesystem>
#include <string>

namespace wirefem::io
{
  void write_file_atomically(const std::filesystem::path &file, const std::string &contents);
} // namespace wirefem::io
