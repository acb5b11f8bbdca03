// Exact vertical errors of dike triangles (terrain/dike_errors.hpp dikeTriangleError), remembered
// across frames. The dikes are re-triangulated every frame, but a triangle's error depends
// only on its three samples, and from one frame to the next almost every dike triangle is the
// same, in the same order (the blocks' meshes mostly come from the LOD cache and buildDikes
// is deterministic): so the frame's dike check computes only the new ones, and finds the old
// ones by walking the last pass's list alongside the new one, not by hashing.
//
// What an error is measured against is the caller's (DikeTriangleMeasure): the exact error
// over a heightfield in memory (ExactDikeError), or a bound from whatever samples a streaming
// source holds. A remembered value stays valid as long as the measure only ever gives bounds
// on the same true error, whatever else changed between the frames.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <polder/terrain/dikes.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::terrain {

// Where a triangle of a frame's DikeMesh sits in it.
struct DikeTriangleRef {
  std::uint32_t vertices[3] = {};  // indices into DikeMesh::vertices
  std::uint32_t owner = 0;         // its DikeMesh::owners entry
};

class DikeTriangleMeasure {
 public:
  virtual ~DikeTriangleMeasure() = default;
  // The height of dike vertex `v`, the mesh's vertex `index`.
  virtual float height(const DikeVertex& v, std::uint32_t index) const = 0;
  // A bound (metres, >= 0) on the triangle's vertical error against the full-resolution
  // surface (dike_errors.hpp); exact where the measure has the full resolution.
  virtual float error(const DikeVertex& a, const DikeVertex& b, const DikeVertex& c,
                      const DikeTriangleRef& where) const = 0;
};

// The exact error, over a heightfield in memory (dikeTriangleError).
class ExactDikeError final : public DikeTriangleMeasure {
 public:
  explicit ExactDikeError(const Heightfield& field) : m_field(field) {}
  float height(const DikeVertex& v, std::uint32_t) const override { return m_field.at(v.x, v.y); }
  float error(const DikeVertex& a, const DikeVertex& b, const DikeVertex& c, const DikeTriangleRef&) const override;

 private:
  const Heightfield& m_field;
};

class DikeErrorCache {
 public:
  explicit DikeErrorCache(const DikeTriangleMeasure& measure) : m_measure(measure) {}

  struct Triangle {
    DikeVertex v[3];
    float error = -1.0f;  // exact vertical error, metres
    float zMin = 0.0f;    // its vertices' height range, metres
    float zMax = 0.0f;
  };

  // Starts a pass over one frame's triangles, all of which it will look up in order; at most
  // `triangles` of them. Grows storage only while passes grow.
  void beginPass(std::size_t triangles);
  // Triangle (a, b, c) with its exact error: the last pass's entry when the walk finds it
  // there, else remembered from earlier or computed.
  const Triangle& lookUp(const DikeVertex& a, const DikeVertex& b, const DikeVertex& c, const DikeTriangleRef& where);

 private:
  void reserveTable(std::size_t triangles);
  float rememberedError(const DikeVertex& a, const DikeVertex& b, const DikeVertex& c, const DikeTriangleRef& where);

  const DikeTriangleMeasure& m_measure;
  std::vector<Triangle> m_previous;  // the last pass, in order
  std::vector<Triangle> m_current;   // this pass so far
  std::size_t m_cursor = 0;          // where in m_previous this pass's next triangle should be
  // Long-term memory of computed errors: open addressing, linear probing, a power of two in
  // size; forgotten wholesale when half full.
  struct Entry {
    DikeVertex v[3];
    float error = -1.0f;  // < 0: empty
  };
  std::vector<Entry> m_entries;
  std::size_t m_used = 0;
};

}  // namespace polder::terrain
