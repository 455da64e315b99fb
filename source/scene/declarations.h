// The scene reader's table of keys (internal to the scene module). Every key
// is written once, in its section's key table (scene/keys/*.json:
// default, documentation, the member it fills, the range of its value), from
// which the build generates declare_sections(); the checks a range cannot
// express stand beside the table (scene/section_checks.cc). The reader sets
// values from the scene file and the command line, checking each against its
// key's pattern, then reads them all into the bound members and checks their
// ranges.
#pragma once

#include <wirefem/scene/parameters.h>
#include <wirefem/scene/scene_reader.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <fmt/format.h>

#include <cmath>
#include <functional>
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

  /// Where a number must lie; checked by Declarations::check_ranges with the
  /// message the enumerator's comment gives.
  enum class Range
  {
    any,
    positive,     ///< "must be positive"
    non_negative, ///< "must not be negative"
    unit,         ///< "must be in [0, 1]"
    open_unit     ///< "must be in (0, 1)"
  };

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

    /// Reads a key's value (as set, or its default) into the member it is
    /// bound to; `where` names the scene file for errors.
    using Reader = std::function<void(const std::string &value, const std::string &where)>;

    /// Declares `path` with its default, pattern and documentation; `read`
    /// fills the bound member from the value.
    void declare(const std::string &path, const std::string &default_value,
                 const Patterns::PatternBase &pattern, const std::string &doc, Reader read)
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
      order.push_back({path, std::move(read), nullptr, Range::any});
    }

    /// `v` as a double; a value the pattern let through but a double cannot
    /// hold (1e-32050, 1e400) is bad input naming the key.
    static double to_double(const std::string &v, const std::string &where, const std::string &path)
    {
      try
        {
          return std::stod(v);
        }
      catch (const std::exception &)
        {
          throw InputError(where + ": " + path + ": '" + v + "' is out of the range of a double");
        }
    }

    /// A real number bound to `target`, which must lie in `range`.
    void number(const std::string &path, const std::string &default_value, const std::string &doc,
                double &target, const Range range = Range::any)
    {
      declare(path, default_value, Patterns::Double(), doc,
              [&target, path](const std::string &v, const std::string &where) {
                target = to_double(v, where, path);
              });
      order.back().value = &target;
      order.back().range = range;
    }

    /// A whole number in [lo, hi] bound to `target`.
    template <typename Int>
    void whole(const std::string &path, const std::string &default_value, const int lo, const int hi,
               const std::string &doc, Int &target)
    {
      declare(
          path, default_value, Patterns::Integer(lo, hi), doc,
          [&target](const std::string &v, const std::string &) { target = static_cast<Int>(std::stol(v)); });
    }

    /// true/false (also yes/no, 1/0) bound to `target`.
    void flag(const std::string &path, const std::string &default_value, const std::string &doc, bool &target)
    {
      declare(path, default_value, Patterns::Bool(), doc,
              [&target](const std::string &v, const std::string &) {
                target = v == "true" || v == "yes" || v == "1";
              });
    }

    /// One of the named options, each standing for a value of `target`.
    template <typename T>
    void choice(const std::string &path, const std::string &default_value,
                const std::vector<std::pair<std::string, T>> &options, const std::string &doc, T &target)
    {
      std::string names;
      for (const auto &o : options)
        names += (names.empty() ? "" : "|") + o.first;
      declare(path, default_value, Patterns::Selection(names), doc,
              [&target, options](const std::string &v, const std::string &) {
                for (const auto &o : options)
                  if (o.first == v)
                    target = o.second;
              });
    }

    /// Comma-separated numbers, at least one.
    void numbers(const std::string &path, const std::string &default_value, const std::string &doc,
                 std::vector<double> &target)
    {
      declare(path, default_value, Patterns::List(Patterns::Double(), 1), doc,
              [&target, path](const std::string &v, const std::string &where) {
                target.clear();
                for (const auto &item : dealii::Utilities::split_string_list(v))
                  target.push_back(to_double(item, where, path));
              });
    }

    /// A number, or 'inf' for no limit.
    void number_or_inf(const std::string &path, const std::string &default_value, const std::string &doc,
                       double &target)
    {
      declare(path, default_value, Patterns::Anything(), doc,
              [&target, path](const std::string &v, const std::string &where) {
                try
                  {
                    target = v == "inf" ? INFINITY : std::stod(v);
                  }
                catch (const std::exception &)
                  {
                    throw InputError(where + ": " + path + ": '" + v + "' is not a number or 'inf'");
                  }
              });
    }

    /// Text matching `pattern`, kept as given.
    void text(const std::string &path, const std::string &default_value, const Patterns::PatternBase &pattern,
              const std::string &doc, std::string &target)
    {
      declare(path, default_value, pattern, doc,
              [&target](const std::string &v, const std::string &) { target = v; });
    }

    /// Fills every bound member from the values set, in declaration order.
    void read_all(const std::string &where) const
    {
      for (const auto &entry : order)
        entry.read(get(entry.path), where);
    }

    /// Throws InputError "where: key: why" for the first number under
    /// `prefix` (a section, "Wire/") outside its range.
    void check_ranges(const std::string &prefix, const std::string &where) const
    {
      for (const auto &entry : order)
        {
          if (entry.path.rfind(prefix, 0) != 0 || entry.range == Range::any)
            continue;
          const double x = *entry.value;
          const bool ok = entry.range == Range::positive       ? x > 0
                          : entry.range == Range::non_negative ? x >= 0
                          : entry.range == Range::unit         ? x >= 0 && x <= 1
                                                               : x > 0 && x < 1;
          if (!ok)
            throw InputError(where + ": " + entry.path + ": " + range_text(entry.range));
        }
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

    /// Every entry outside Output, and the Output keys that set what the
    /// files hold (the row and VTU spacing), as "Section/Key = value"
    /// lines, sorted by key; numbers written in one canonical form, so
    /// that 25 and 25.0 read alike.
    std::string fingerprint() const
    {
      std::string out;
      for (const auto &[key, entry] : table)
        {
          if (key.rfind("output/", 0) == 0 && key != "output/interval" && key != "output/vtu interval")
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

    static const char *range_text(const Range range)
    {
      switch (range)
        {
        case Range::positive:
          return "must be positive";
        case Range::non_negative:
          return "must not be negative";
        case Range::unit:
          return "must be in [0, 1]";
        case Range::open_unit:
          return "must be in (0, 1)";
        default:
          return "";
        }
    }

    struct Entry
    {
      std::string path;
      std::unique_ptr<Patterns::PatternBase> pattern;
    };
    /// A declared key in declaration order, with the member it fills.
    struct Binding
    {
      std::string path;
      Reader read;
      const double *value; ///< numbers only: checked against range
      Range range;
    };
    ParameterHandler &prm;
    std::map<std::string, Entry> table;
    std::vector<Binding> order;
  };

  /// Declares the keys of every section, bound to the members of `s`
  /// (generated from scene/keys/*.json).
  void declare_sections(Declarations &d, Scene &s);

  /// The injection set-up's cavity shape and channel placement
  /// (section_checks.cc): a wall that cannot be built, channels off the wall,
  /// overlapping or running back through the cavity, an initial wire that
  /// overlaps the wall.
  void validate_wall(const Scene &s, const std::string &where);

  /// Throws InputError "where: key: why" unless ok.
  inline void check(const bool ok, const std::string &where, const std::string &key, const std::string &why)
  {
    if (!ok)
      throw InputError(where + ": " + key + ": " + why);
  }
} // namespace wirefem::scene
