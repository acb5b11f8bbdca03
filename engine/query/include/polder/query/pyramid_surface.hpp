// The full resolution of a pyramid (docs/streaming.md) as a TrueSurface, read from its level-0
// tiles as the queries reach them, a bounded number of tiles held at once: the truth a flight
// over a DEM larger than memory is measured against.
//
// height() is the heightfield triangulation's (terrain/heightfield.hpp) at the point, as
// QueryScene::height answers it for the same DEM in memory. meets() descends the quadtree
// through the boxes of the nodes' exact height ranges and tests the cells of the level-0
// nodes the ray's box reaches in double precision.
//
// A tile that cannot be read answers as if there were no surface there; readFailures() counts
// such reads and firstFailure() keeps the first message, so a measurement can be refused.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include <polder/cache/lru_cache.hpp>
#include <polder/query/true_surface.hpp>
#include <polder/terrain/pyramid.hpp>

namespace polder::query {

class PyramidSurface final : public TrueSurface {
 public:
  // `tileBytes`: the most bytes of level-0 tiles held at once.
  explicit PyramidSurface(std::shared_ptr<const terrain::Pyramid> pyramid, std::size_t tileBytes = 32u << 20);

  std::optional<double> height(double x, double y) const override;
  bool meets(const QueryRay& ray) const override;

  std::size_t readFailures() const { return m_failures.load(); }
  std::string firstFailure() const;

 private:
  using Tile = std::shared_ptr<const terrain::Heightfield>;
  // The level-0 tile of node (bx, by), or null when it cannot be read.
  Tile levelZeroTile(int bx, int by) const;
  bool meetsCells(const terrain::NodeId& node, const QueryRay& ray, double t0, double t1) const;

  std::shared_ptr<const terrain::Pyramid> m_pyramid;
  mutable std::mutex m_mutex;  // guards m_tiles and m_firstFailure
  mutable cache::LruCache<std::uint64_t, Tile> m_tiles;
  mutable std::string m_firstFailure;
  mutable std::atomic<std::size_t> m_failures{0};
};

}  // namespace polder::query
