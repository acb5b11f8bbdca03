#include "number_rules.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace polder::cli {
namespace {

std::string formatBound(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

// Empty when `text` is a number within the rule, else what is wrong with it ("must be ...").
std::string problemWith(std::string_view text, const NumberRule& rule, double& value) {
  const char* end = text.data() + text.size();
  const auto parsed = std::from_chars(text.data(), end, value);
  if (text.empty() || parsed.ec != std::errc() || parsed.ptr != end)
    return "must be " + describe(rule) + ", not '" + std::string(text) + "'";
  if (!checkNumber(value, rule, "")) return "must be " + describe(rule) + ", not " + std::string(text);
  return {};
}

}  // namespace

std::string describe(const NumberRule& rule) {
  std::string text = rule.whole ? "a whole number" : "a finite number";
  if (*rule.unit) text += std::string(" of ") + rule.unit;
  if (rule.lowestOpen)
    text += " above " + formatBound(rule.lowest) + " and at most " + formatBound(rule.highest);
  else
    text += " in " + formatBound(rule.lowest) + ".." + formatBound(rule.highest);
  return text;
}

Result<double> checkNumber(double value, const NumberRule& rule, std::string_view what) {
  const bool inRange = std::isfinite(value) && (rule.lowestOpen ? value > rule.lowest : value >= rule.lowest) &&
                       value <= rule.highest && (!rule.whole || value == std::floor(value));
  if (!inRange) return makeError(ErrorKind::InvalidArgument, std::string(what) + " must be " + describe(rule));
  return value;
}

Result<double> checkNumber(std::string_view text, const NumberRule& rule, std::string_view what) {
  double value = 0.0;
  const std::string problem = problemWith(text, rule, value);
  if (!problem.empty()) return makeError(ErrorKind::InvalidArgument, std::string(what) + " " + problem);
  return value;
}

CLI::Validator numberIn(const NumberRule& rule) {
  return CLI::Validator(
      [rule](std::string& text) -> std::string {
        double value = 0.0;
        return problemWith(text, rule, value);  // CLI11 puts the option's name before it
      },
      describe(rule));
}

}  // namespace polder::cli
