// Text forms of the DEM options, as the command line gives them.
#pragma once

#include <string>
#include <string_view>

#include <polder/result.hpp>
#include <polder/terrain/dem.hpp>

namespace polder::terrain {

// Parses `WxH:u16|i16|f32[:le|be]` (little-endian unless `:be`), e.g. "1024x1024:u16" or
// "513x257:f32:be". Fails with InvalidArgument naming the text.
Result<RawLayout> parseRawLayout(std::string_view text);

// The text parseRawLayout reads back ("1024x1024:u16:le").
std::string rawLayoutName(const RawLayout& layout);

// Parses `auto|greyscale|terrain-rgb|terrarium`. Fails with InvalidArgument naming the text.
Result<HeightEncoding> parseHeightEncoding(std::string_view text);

// The name parseHeightEncoding accepts ("terrain-rgb", ...).
const char* heightEncodingName(HeightEncoding encoding);

}  // namespace polder::terrain
