// Third-party libraries' messages may span lines; Polder's errors are one line.
#pragma once

#include <string>
#include <string_view>

namespace polder {

// The text with line breaks turned into "; ", trailing separators dropped, and
// "no details given" for an empty message.
inline std::string oneLine(std::string_view text) {
  std::string line;
  for (char c : text) {
    if (c == '\n' || c == '\r') {
      if (!line.empty() && line.back() != ' ') line += "; ";
    } else {
      line += c;
    }
  }
  while (!line.empty() && (line.back() == ' ' || line.back() == ';')) line.pop_back();
  return line.empty() ? "no details given" : line;
}

}  // namespace polder
