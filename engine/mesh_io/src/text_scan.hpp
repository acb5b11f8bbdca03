// Small text helpers the structure checks and the writers share (no third-party types).
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace polder::mesh_io::detail {

inline bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Splits a line into white-space separated tokens.
inline void splitTokens(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isBlank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !isBlank(line[i])) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
}

// Whether the token is a number Assimp's parser takes: an optional sign, then a decimal
// number (or nan / inf). Commas as decimal points are not accepted.
inline bool isNumber(std::string_view token) {
  if (!token.empty() && (token.front() == '+' || token.front() == '-')) token.remove_prefix(1);
  if (token.empty() || token.front() == '+' || token.front() == '-') return false;
  double value = 0.0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  // Out-of-range values are numbers too (they become inf; the position check reports them).
  return end == token.data() + token.size() && (error == std::errc() || error == std::errc::result_out_of_range);
}

// A whole-token integer with an optional sign, or nullopt.
inline std::optional<std::int64_t> parseInteger(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  std::int64_t value = 0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (token.empty() || error != std::errc() || end != token.data() + token.size()) return std::nullopt;
  return value;
}

// Quotes a token from a file for an error message, cut short and with control bytes escaped.
inline std::string quoted(std::string_view token) {
  std::string text = "'";
  for (std::size_t i = 0; i < token.size() && i < 40; ++i) {
    const unsigned char c = static_cast<unsigned char>(token[i]);
    if (c >= 32 && c < 127) {
      text += char(c);
    } else {
      static constexpr char kHex[] = "0123456789abcdef";
      text += "\\x";
      text += kHex[c >> 4];
      text += kHex[c & 15];
    }
  }
  if (token.size() > 40) text += "...";
  return text + "'";
}

}  // namespace polder::mesh_io::detail
