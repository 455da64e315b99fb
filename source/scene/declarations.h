// The scene reader's table of keys (internal to the scene module): each
// parameter struct declares its keys into it and parses them from it
// (scene/*_parameters.cc), and the reader sets values from the scene file
// and the command line, checking each against its key's pattern.
#pragma once

#include <wirefem/scene/parameters.h>
#include <wirefem/scene/scene_reader.h>

#include <deal.II/base/parameter_handler.h>

#include <fmt/format.h>

#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace wirefem::scene
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;

  inline std::string trim(const std::string &s)
  {
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos)
      return "";
    const auto e = s.find_last_not_of(" \t\r\n");
    return s.substr(b, e - b + 1);
  }

  inline std::vector<std::string> split_path(const std::string &key)
  {
    std::vector<std::string> parts;
    std::stringstream ss(key);
    std::string part;
    while (std::getline(ss, part, '/'))
      parts.push_back(trim(part));
    return parts;
  }

  // ParameterHandler only Asserts (debug builds) on undeclared keys, so the
  // reader keeps its own table of declared keys and their patterns: every
  // value is checked here before it reaches the handler.
  class Declarations
  {
  public:
    explicit Declarations(ParameterHandler &prm)
      : prm(prm)
    {
    }

    void declare(const std::string &path, const std::string &default_value,
                 const Patterns::PatternBase &pattern, const std::string &doc)
    {
      auto parts = split_path(path);
      const std::string name = parts.back();
      parts.pop_back();
      for (const auto &s : parts)
        prm.enter_subsection(s);
      prm.declare_entry(name, default_value, pattern, doc);
      for (std::size_t i = 0; i < parts.size(); ++i)
        prm.leave_subsection();
      table[canonical(path)] = {path, pattern.clone()};
    }

    /// Sets `key` to `value`; `where` names the file (and line) for errors.
    void set(const std::string &where, const std::string &key, const std::string &value)
    {
      const auto it = table.find(canonical(key));
      if (it == table.end())
        throw InputError(where + ": " + key + ": no such key (see --print-parameters)");
      if (!it->second.pattern->match(value))
        throw InputError(where + ": " + it->second.path + ": '" + value +
                         "' is not a valid value; expected " +
                         it->second.pattern->description(Patterns::PatternBase::Text));
      auto parts = split_path(it->second.path);
      const std::string name = parts.back();
      parts.pop_back();
      for (const auto &s : parts)
        prm.enter_subsection(s);
      prm.set(name, value);
      for (std::size_t i = 0; i < parts.size(); ++i)
        prm.leave_subsection();
    }

    std::string get(const std::string &path) const
    {
      auto parts = split_path(path);
      const std::string name = parts.back();
      parts.pop_back();
      for (const auto &s : parts)
        prm.enter_subsection(s);
      const std::string value = prm.get(name);
      for (std::size_t i = 0; i < parts.size(); ++i)
        prm.leave_subsection();
      return value;
    }

    double get_double(const std::string &path) const { return std::stod(get(path)); }
    bool get_bool(const std::string &path) const
    {
      const std::string v = get(path);
      return v == "true" || v == "yes" || v == "1";
    }

    /// Every entry outside Output as "Section/Key = value" lines, sorted
    /// by key; numbers written in one canonical form, so that 25 and 25.0
    /// read alike.
    std::string fingerprint() const
    {
      std::string out;
      for (const auto &[key, entry] : table)
        {
          if (key.rfind("output/", 0) == 0)
            continue;
          std::string value = get(entry.path);
          try
            {
              std::size_t used = 0;
              const double x = std::stod(value, &used);
              if (used == value.size())
                value = fmt::format("{}", x);
            }
          catch (const std::exception &)
            {
            }
          out += entry.path + " = " + value + "\n";
        }
      return out;
    }

  private:
    // Keys match regardless of spacing around '/' and of case, so that
    // "contact/friction/static coefficient" is accepted on the command line.
    static std::string canonical(const std::string &key)
    {
      std::string out;
      for (const auto &p : split_path(key))
        {
          if (!out.empty())
            out += '/';
          for (const char c : p)
            out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        }
      return out;
    }

    struct Entry
    {
      std::string path;
      std::unique_ptr<Patterns::PatternBase> pattern;
    };
    ParameterHandler &prm;
    std::map<std::string, Entry> table;
  };

  /// Throws InputError "where: key: why" unless ok.
  inline void check(const bool ok, const std::string &where, const std::string &key, const std::string &why)
  {
    if (!ok)
      throw InputError(where + ": " + key + ": " + why);
  }
} // namespace wirefem::scene
