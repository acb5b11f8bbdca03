// Small text helpers the adapter shares (no third-party types).
#pragma once

#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>

#include <polder/one_line.hpp>

namespace polder::terrain::io {

using polder::oneLine;

// Shortest text that reads back as the same double.
inline std::string formatExact(double value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

// A whole-string finite number, or nullopt.
inline std::optional<double> parseNumber(std::string_view text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
    return std::nullopt;
  return value;
}

// PNG text keys of a Polder height PNG (see image_writer.hpp).
inline constexpr const char* kPngSpacingXKey = "polder:spacingX";
inline constexpr const char* kPngSpacingYKey = "polder:spacingY";
inline constexpr const char* kPngMetresPerUnitKey = "polder:metresPerUnit";
inline constexpr const char* kPngOffsetKey = "polder:offsetM";

}  // namespace polder::terrain::io
