// Reading a scene: a prm file (deal.II ParameterHandler format) plus
// "Section/Key=value" overrides, checked key by key so that every error names
// the file, the key and the reason in one line.
#pragma once

#include <wirefem/core/input_error.h>
#include <wirefem/scene/parameters.h>

#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace wirefem::scene
{
  /// Bad input: a one-line message "FILE: KEY: reason" (exit status 2).
  using core::InputError;

  /// Reads `prm_file` (may be empty: defaults only) and applies `overrides`
  /// ("Section/Sub/Key=value") in order. Throws InputError on bad input.
  Scene read_scene(const std::string &prm_file, const std::vector<std::string> &overrides);

  /// Prints every key with its default and documentation in prm format.
  void print_parameters(std::ostream &out);
} // namespace wirefem::scene
