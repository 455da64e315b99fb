// Bad input, wherever the program meets it: a scene or sweep file, a shape
// to analyse, a series to resume onto. One type, so that every such error
// ends the same way: a one-line message naming the file (and line, key) and
// the reason, exit status 2.
#pragma once

#include <wirefem/core/printable.h>

#include <stdexcept>
#include <string>

namespace wirefem::core
{
  class InputError : public std::runtime_error
  {
  public:
    /// The message as given, with what cannot be printed on one line
    /// (newlines, control characters, bytes that are not UTF-8) as \xNN.
    explicit InputError(const std::string &what)
      : std::runtime_error(printable(what))
    {
    }
  };
} // namespace wirefem::core
