// Text from files and command lines made safe to print on one line of a
// terminal: what every error message that quotes input goes through.
#pragma once

#include <string>

namespace wirefem::core
{
  /// `text` safe for a terminal, on one line: control characters, bytes
  /// that are not UTF-8 and the C1 controls (a binary scene file's escape
  /// sequences) as \xNN.
  inline std::string printable(const std::string &text)
  {
    std::string out;
    const auto *p = reinterpret_cast<const unsigned char *>(text.data());
    const std::size_t n = text.size();
    for (std::size_t i = 0; i < n;)
      {
        const unsigned char c = p[i];
        // Length of a well-formed UTF-8 sequence starting here (0: none).
        std::size_t len = c >= 0x20 && c < 0x7f    ? 1
                          : c >= 0xc2 && c <= 0xdf ? 2
                          : c >= 0xe0 && c <= 0xef ? 3
                          : c >= 0xf0 && c <= 0xf4 ? 4
                                                   : 0;
        for (std::size_t k = 1; k < len; ++k)
          if (i + k >= n || (p[i + k] & 0xc0) != 0x80)
            len = 0;
        if (len == 2 && c == 0xc2 && p[i + 1] < 0xa0) // U+0080..U+009F
          len = 0;
        if (len == 0)
          {
            static const char hex[] = "0123456789abcdef";
            out += {'\\', 'x', hex[c >> 4], hex[c & 15]};
            ++i;
          }
        else
          {
            out.append(text, i, len);
            i += len;
          }
      }
    return out;
  }
} // namespace wirefem::core
