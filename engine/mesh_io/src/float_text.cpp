#include "float_text.hpp"

#include <assimp/fast_atof.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <string_view>

namespace polder::mesh_io::detail {
namespace {

// fast_atoreal_move throws its template argument on bad text; the default one is not
// exported by Debian's libassimp, and nothing here needs more than "it failed".
struct ParseFailure {
  template <class... Parts>
  explicit ParseFailure(Parts&&...) {}
};

bool readsBackAs(const char* text, float value) {
  float parsed = 0.0f;
  try {
    Assimp::fast_atoreal_move<float, ParseFailure>(text, parsed);
  } catch (const ParseFailure&) {
    return false;
  }
  return std::memcmp(&parsed, &value, sizeof value) == 0;
}

// The text of to_chars into `buffer` (null-terminated), as a view.
template <class... Format>
std::string_view format(char (&buffer)[64], float value, Format... format) {
  const auto result = std::to_chars(buffer, buffer + sizeof buffer - 1, value, format...);
  const std::size_t length = result.ec == std::errc() ? std::size_t(result.ptr - buffer) : 0;
  buffer[length] = '\0';  // an empty text never reads back as a float
  return {buffer, length};
}

// Assimp computes mantissa * powf(10, exponent) in float: look for a float mantissa whose
// product with some power of ten lands exactly on `value`, near the obvious exponent.
bool findMantissaExponent(float value, std::string& out) {
  if (value == 0.0f) return false;
  const int obvious = int(std::floor(std::log10(std::fabs(double(value)))));
  char buffer[64];
  for (int distance = 0; distance <= 14; ++distance) {
    for (int exponent : {obvious - distance, obvious + distance}) {
      const float power = std::pow(10.0f, float(exponent));
      if (!(power > 0.0f) || !std::isfinite(power)) continue;
      const float estimate = float(double(value) / double(power));
      float below = estimate, above = estimate;
      for (int step = 0; step < 4; ++step) {
        for (float mantissa : {below, above}) {
          if (!std::isfinite(mantissa) || mantissa * power != value) continue;
          std::string text(format(buffer, mantissa));
          text += 'e';
          text += std::to_string(exponent);
          if (readsBackAs(text.c_str(), value)) {
            out += text;
            return true;
          }
        }
        below = std::nextafter(below, -INFINITY);
        above = std::nextafter(above, INFINITY);
      }
      if (distance == 0) break;  // obvious - 0 and obvious + 0 are the same
    }
  }
  return false;
}

}  // namespace

void appendFloat(std::string& out, float value) {
  char buffer[64];
  const std::string_view shortest = format(buffer, value);
  if (!std::isfinite(value) || readsBackAs(buffer, value)) {
    out += shortest;
    return;
  }
  char other[64];
  // Fixed notation only where the integer part fits Assimp's 64-bit integer parsing.
  if (const std::string_view fixed = format(other, value, std::chars_format::fixed);
      std::fabs(value) < 1e15f && readsBackAs(other, value)) {
    out += fixed;
    return;
  }
  if (const std::string_view nineDigits = format(other, value, std::chars_format::general, 9);
      readsBackAs(other, value)) {
    out += nineDigits;
    return;
  }
  if (findMantissaExponent(value, out)) return;
  out += shortest;
}

}  // namespace polder::mesh_io::detail
