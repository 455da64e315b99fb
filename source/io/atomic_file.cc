#include <wirefem/io/atomic_file.h>

#include <fstream>

namespace wirefem::io
{
  void write_file_atomically(const std::filesystem::path &file, const std::string &contents)
  {
    auto tmp = file;
    tmp += ".tmp";
    std::ofstream(tmp.string()) << contents;
    std::filesystem::rename(tmp, file);
  }
} // namespace wirefem::io
