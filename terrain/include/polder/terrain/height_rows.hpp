// A raster of heights read a band of rows at a time: how Polder reads DEMs larger than memory
// (polder prep, polder info). Row 0 is the south edge, as in heightfield.hpp.
//
// Sources: an in-memory Heightfield (HeightfieldRows, here) and DEM files
// (openDemRows in the OpenImageIO adapter, <polder/terrain/dem_rows.hpp>).
//
// Threads: one source is used by one thread at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include <polder/result.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::terrain {

class HeightRows {
 public:
  virtual ~HeightRows() = default;

  virtual int width() const = 0;
  virtual int height() const = 0;
  virtual double spacingX() const = 0;  // metres
  virtual double spacingY() const = 0;

  // Rows [y0, y0 + count) into `out` (count * width() metres, row y0 first, each row west to
  // east). Any order of calls works; reading south to north in increasing y0 is the fast one.
  // Errors (never asserts): InvalidArgument for a range outside the raster or an `out` of
  // another size; Io and InvalidData (a truncated file, a non-finite height) naming the file.
  virtual Status readRows(int y0, int count, std::span<float> out) = 0;
};

// Rows of a Heightfield kept in memory (the field must outlive it).
class HeightfieldRows final : public HeightRows {
 public:
  explicit HeightfieldRows(const Heightfield& field) : m_field(field) {}
  int width() const override { return m_field.width; }
  int height() const override { return m_field.height; }
  double spacingX() const override { return m_field.spacingX; }
  double spacingY() const override { return m_field.spacingY; }
  Status readRows(int y0, int count, std::span<float> out) override {
    if (y0 < 0 || count < 0 || y0 + count > m_field.height)
      return makeError(ErrorKind::InvalidArgument, "rows outside the heightfield");
    const std::size_t values = std::size_t(count) * std::size_t(m_field.width);
    if (out.size() != values) return makeError(ErrorKind::InvalidArgument, "row buffer of the wrong size");
    const auto first = m_field.heights.begin() + std::ptrdiff_t(std::size_t(y0) * std::size_t(m_field.width));
    std::copy(first, first + std::ptrdiff_t(values), out.begin());
    return {};
  }

 private:
  const Heightfield& m_field;
};

}  // namespace polder::terrain
