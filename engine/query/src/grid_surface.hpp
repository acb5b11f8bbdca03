// A heightfield's full-resolution surface as the query scene stores it: one float vertex
// per sample in the scene frame (the buffer Embree's grid primitives share), plus the exact
// double-precision geometry of the same triangles for closed-form heights and refined hits.
// No Embree in here.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include <polder/terrain/heightfield.hpp>

namespace polder::query::detail {

struct SurfaceHit {
  double t = 0.0;
  glm::dvec3 normal{0.0, 0.0, 1.0};  // unit, not yet oriented against the ray
};

class GridSurface {
 public:
  // Stores the samples of `field` relative to `sceneOrigin` (x and y only: heights stay
  // absolute, they are floats already). The field must be at least 2x2.
  GridSurface(const terrain::Heightfield& field, const glm::dvec3& sceneOrigin);

  int width() const { return m_width; }
  int height() const { return m_height; }

  // The float xyz buffer, one vertex per sample, row-major from the south row, padded by
  // one float so that SIMD loads of the last vertex stay inside it.
  const float* vertexData() const { return m_vertices.data(); }
  std::size_t vertexCount() const { return std::size_t(m_width) * std::size_t(m_height); }
  std::size_t byteSize() const { return m_vertices.capacity() * sizeof(float); }

  // Exact world position of sample (x, y).
  glm::dvec3 sample(int x, int y) const {
    return {x * m_spacingX, y * m_spacingY,
            double(m_vertices[(std::size_t(y) * std::size_t(m_width) + std::size_t(x)) * 3 + 2])};
  }

  // Height of the triangulation at world (x, y); nullopt outside the footprint or where a
  // corner of the triangle is not finite.
  std::optional<double> heightAt(double x, double y) const;

  // The nearest hit with t in [tMin, tMax] of the ray with the convention's triangles of
  // cell (cx, cy), or, if none, of the cells around it. Used to correct a hit Embree found
  // in single precision, whose cell may be off by one near an edge.
  std::optional<SurfaceHit> intersectNear(const glm::dvec3& origin, const glm::dvec3& direction, double tMin,
                                          double tMax, int cx, int cy) const;

 private:
  std::optional<SurfaceHit> intersectCells(const glm::dvec3& origin, const glm::dvec3& direction, double tMin,
                                           double tMax, int cx0, int cy0, int cx1, int cy1) const;

  int m_width = 0;
  int m_height = 0;
  double m_spacingX = 1.0;
  double m_spacingY = 1.0;
  std::vector<float> m_vertices;
};

}  // namespace polder::query::detail
