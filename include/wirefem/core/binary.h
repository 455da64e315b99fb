// Raw binary read/write of trivially copyable values and vectors, for
// checkpoints that are read back by the same build on the same machine.
#pragma once

#include <cstdint>
#include <istream>
#include <ostream>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace wirefem::core
{
  template <typename T>
  void write_raw(std::ostream &out, const T &value)
  {
    static_assert(std::is_trivially_copyable_v<T>);
    out.write(reinterpret_cast<const char *>(&value), sizeof(T));
  }

  template <typename T>
  T read_raw(std::istream &in)
  {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    if (!in.read(reinterpret_cast<char *>(&value), sizeof(T)))
      throw std::runtime_error("checkpoint is truncated");
    return value;
  }

  template <typename T>
  void write_vector(std::ostream &out, const std::vector<T> &v, std::size_t begin, std::size_t end)
  {
    write_raw(out, static_cast<std::uint64_t>(begin));
    write_raw(out, static_cast<std::uint64_t>(end));
    if (end > begin)
      out.write(reinterpret_cast<const char *>(v.data() + begin), sizeof(T) * (end - begin));
  }

  /// Reads into v[begin, end) as written by write_vector; v must be large enough.
  template <typename T>
  void read_vector(std::istream &in, std::vector<T> &v)
  {
    const auto begin = read_raw<std::uint64_t>(in);
    const auto end = read_raw<std::uint64_t>(in);
    if (end < begin || end > v.size())
      throw std::runtime_error("checkpoint does not fit this scene");
    if (end > begin && !in.read(reinterpret_cast<char *>(v.data() + begin), sizeof(T) * (end - begin)))
      throw std::runtime_error("checkpoint is truncated");
  }

  /// Size (end - begin) of the vector written next, without consuming it.
  inline std::size_t peek_vector_size(std::istream &in)
  {
    const auto pos = in.tellg();
    read_raw<std::uint64_t>(in); // begin: vectors read this way are written from 0
    const auto end = read_raw<std::uint64_t>(in);
    in.seekg(pos);
    return end;
  }

  template <typename Map>
  void write_map(std::ostream &out, const Map &m)
  {
    write_raw(out, static_cast<std::uint64_t>(m.size()));
    for (const auto &kv : m)
      {
        write_raw(out, kv.first);
        write_raw(out, kv.second);
      }
  }

  template <typename Map>
  void read_map(std::istream &in, Map &m)
  {
    m.clear();
    const auto n = read_raw<std::uint64_t>(in);
    for (std::uint64_t i = 0; i < n; ++i)
      {
        const auto key = read_raw<typename Map::key_type>(in);
        m[key] = read_raw<typename Map::mapped_type>(in);
      }
  }
} // namespace wirefem::core
