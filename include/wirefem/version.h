#pragma once

namespace wirefem
{
  /// "MAJOR.MINOR.PATCH (commit HASH)": the project version and the git
  /// commit the binary was built from, with "-dirty" when the tree had
  /// uncommitted changes. Printed by `wirefem --version` and recorded in
  /// every summary.json, so a result can be traced to the code that made it.
  const char *version();
} // namespace wirefem
