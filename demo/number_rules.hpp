// The numbers `polder` accepts, one rule per quantity, shared by the command line and the
// scene file so that both refuse the same values with the same words: finite, within the
// quantity's range, whole where a count is meant, never wrapped into an unsigned type.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include <polder/result.hpp>

namespace polder::cli {

struct NumberRule {
  double lowest = 0.0;  // inclusive bounds
  double highest = 0.0;
  bool whole = false;       // a count or an index: no fraction
  bool lowestOpen = false;  // the lowest bound itself is refused (a positive length, say)
  const char* unit = "";    // for the message: "metres", "pixels", ...
};

// The quantities the commands and the scene file share.
namespace rules {
inline constexpr NumberRule kTauPx{0.01, 1000.0, false, false, "pixels"};
inline constexpr NumberRule kAltitudeM{0.0, 1e6, false, false, "metres"};
inline constexpr NumberRule kSpeedMps{0.0, 1e5, false, true, "metres per second"};
inline constexpr NumberRule kFps{1.0, 1000.0, false, false, "frames per second"};
inline constexpr NumberRule kFrames{1.0, 1e7, true, false, "frames"};
inline constexpr NumberRule kFovDeg{1.0, 179.0, false, true, "degrees"};
inline constexpr NumberRule kPitchDeg{-90.0, 90.0, false, false, "degrees"};
inline constexpr NumberRule kBudgetTriangles{1.0, 1e9, true, false, "triangles"};
inline constexpr NumberRule kAlpha{0.0, 16.0, false, true, ""};
inline constexpr NumberRule kSpacingM{1e-3, 1e6, false, false, "metres"};
inline constexpr NumberRule kZScale{-1e6, 1e6, false, false, ""};  // and not 0
inline constexpr NumberRule kCacheMb{0.0, 1 << 20, true, false, "MiB"};
inline constexpr NumberRule kMemoryMb{16.0, 1 << 20, true, false, "MiB"};
inline constexpr NumberRule kRegions{1.0, 100000.0, true, false, "regions"};
inline constexpr NumberRule kTriangles{1.0, 1e9, true, false, "triangles"};
inline constexpr NumberRule kSamples{1.0, 1e8, true, false, "samples"};
inline constexpr NumberRule kSeed{0.0, 4294967295.0, true, false, ""};
inline constexpr NumberRule kThreads{0.0, 1024.0, true, false, "threads"};
inline constexpr NumberRule kMeasureEvery{0.0, 1e7, true, false, "frames"};
inline constexpr NumberRule kEvery{1.0, 1e7, true, false, "frames"};
inline constexpr NumberRule kMaxErrorM{0.0, 1e6, false, true, "metres"};
// Positions, directions and angles: far beyond any terrain, well inside what ray tracing and
// single-precision matrices take.
inline constexpr NumberRule kCoordinateM{-1e9, 1e9, false, false, ""};
inline constexpr NumberRule kRepeat{1.0, 100000.0, true, false, "copies"};
}  // namespace rules

// "must be ..." for the rule: "a finite number of pixels in 0.01..1000".
std::string describe(const NumberRule& rule);

// The value, or why it breaks the rule, as "WHAT must be ...". InvalidArgument.
Result<double> checkNumber(double value, const NumberRule& rule, std::string_view what);
// The text as a whole number or decimal, then checked: "-1", "nan", "1e400", "3x" are refused
// before any conversion to the option's type could wrap or round them.
Result<double> checkNumber(std::string_view text, const NumberRule& rule, std::string_view what);

// A CLI11 check for an option: its message is checkNumber's.
CLI::Validator numberIn(const NumberRule& rule);

// An option holding a quantity: checked by its rule, its default shown in --help.
template <typename T>
CLI::Option* addNumberOption(CLI::App& command, const std::string& name, T& value, const std::string& description,
                             const NumberRule& rule) {
  return command.add_option(name, value, description)->check(numberIn(rule))->capture_default_str();
}

}  // namespace polder::cli
