// Bad input, wherever the program meets it: a scene or sweep file, a shape
// to analyse, a series to resume onto. One type, so that every such error
// ends the same way: a one-line message naming the file (and line, key) and
// the reason, exit status 2.
#pragma once

#include <stdexcept>

namespace wirefem::core
{
  class InputError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };
} // namespace wirefem::core
