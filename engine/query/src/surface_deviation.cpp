#include <polder/query/surface_deviation.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <polder/mix_bits.hpp>
#include <polder/thread_pool.hpp>

#include "closest_point_scene.hpp"

namespace polder::query {

namespace {

constexpr std::uint64_t kGoldenGamma = 0x9e3779b97f4a7c15ull;  // splitmix64's increment
// Samples per unit of work. Fixed (not per thread) so that the partial sums, added in
// chunk order, give the same result for any thread count.
constexpr std::size_t kChunkSamples = 4096;

// Random numbers indexed by (sample, word): splitmix64 evaluated at a counter, so each
// sample's point depends only on the seed and its index, not on which thread draws it.
class SampleRandom {
 public:
  SampleRandom(std::uint64_t seed, std::uint64_t stream) : m_key(mixBits(seed) ^ mixBits(stream + kGoldenGamma)) {}

  // Uniform in [0, 1).
  double uniform(std::size_t sample, std::uint64_t word) const {
    const std::uint64_t counter = std::uint64_t(sample) * 3 + word + 1;
    return double(mixBits(m_key + counter * kGoldenGamma) >> 11) * 0x1.0p-53;
  }

 private:
  std::uint64_t m_key;
};

// One mesh prepared for sampling.
struct Surface {
  const mesh::TriangleMesh* mesh = nullptr;
  std::vector<double> cumulativeArea;       // per triangle: the areas of it and all before it
  std::vector<std::uint32_t> usedVertices;  // ascending: each vertex some triangle uses
  std::size_t randomSamples = 0;            // none where the whole surface has zero area
  SampleRandom random{0, 0};

  std::size_t sampleCount() const { return randomSamples + usedVertices.size(); }

  glm::dvec3 vertex(std::uint32_t triangle, int corner) const {
    return glm::dvec3(mesh->positions[mesh->indices[3 * std::size_t(triangle) + std::size_t(corner)]]);
  }
};

// A point on a surface and where it lies there.
struct Sample {
  glm::dvec3 point{0.0};
  std::uint32_t triangle = 0;
  glm::dvec3 weights{1.0, 0.0, 0.0};    // barycentric, of the triangle's corners
  std::optional<std::uint32_t> vertex;  // set for vertex samples
};

Surface prepareSurface(const mesh::TriangleMesh& mesh, std::size_t randomSamples, std::uint64_t seed,
                       std::uint64_t stream) {
  Surface surface;
  surface.mesh = &mesh;
  surface.random = SampleRandom(seed, stream);
  const std::size_t triangles = mesh.triangleCount();
  surface.cumulativeArea.resize(triangles);
  std::vector<bool> used(mesh.positions.size(), false);
  double total = 0.0;
  for (std::size_t t = 0; t < triangles; ++t) {
    const glm::dvec3 a = surface.vertex(std::uint32_t(t), 0), b = surface.vertex(std::uint32_t(t), 1),
                     c = surface.vertex(std::uint32_t(t), 2);
    total += 0.5 * glm::length(glm::cross(b - a, c - a));
    surface.cumulativeArea[t] = total;
    for (int k = 0; k < 3; ++k) used[mesh.indices[3 * t + std::size_t(k)]] = true;
  }
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (used[v]) surface.usedVertices.push_back(std::uint32_t(v));
  }
  surface.randomSamples = total > 0.0 ? randomSamples : 0;
  return surface;
}

// Sample i of the surface: the random points first, then the used vertices.
Sample sampleOf(const Surface& surface, std::size_t i) {
  Sample sample;
  if (i >= surface.randomSamples) {
    const std::uint32_t vertex = surface.usedVertices[i - surface.randomSamples];
    sample.point = glm::dvec3(surface.mesh->positions[vertex]);
    sample.vertex = vertex;
    return sample;
  }
  // Area-weighted and stratified: sample i falls uniformly in the i-th of randomSamples
  // equal slices of the cumulative area, so consecutive samples lie on the same or nearby
  // triangles (which lets each closest-point search start from the last one's answer) and
  // the area is covered more evenly than by independent draws. Zero-area triangles span
  // empty intervals and are never picked.
  const double total = surface.cumulativeArea.back();
  const double target = (double(i) + surface.random.uniform(i, 0)) / double(surface.randomSamples) * total;
  const auto found = std::upper_bound(surface.cumulativeArea.begin(), surface.cumulativeArea.end(), target);
  const std::size_t triangle =
      std::min(std::size_t(found - surface.cumulativeArea.begin()), surface.cumulativeArea.size() - 1);
  // Uniform in the triangle (Osada et al., "Shape distributions", 2002, eq. 1).
  const double s = std::sqrt(surface.random.uniform(i, 1)), r = surface.random.uniform(i, 2);
  sample.triangle = std::uint32_t(triangle);
  sample.weights = glm::dvec3(1.0 - s, s * (1.0 - r), s * r);
  sample.point = sample.weights.x * surface.vertex(sample.triangle, 0) +
                 sample.weights.y * surface.vertex(sample.triangle, 1) +
                 sample.weights.z * surface.vertex(sample.triangle, 2);
  return sample;
}

glm::dvec3 colourAt(const mesh::TriangleMesh& mesh, std::uint32_t triangle, const glm::dvec3& weights) {
  glm::dvec3 colour(0.0);
  for (int k = 0; k < 3; ++k) {
    colour +=
        weights[k] * glm::dvec3(glm::vec3(mesh.colours[mesh.indices[3 * std::size_t(triangle) + std::size_t(k)]]));
  }
  return colour;
}

glm::dvec3 colourAt(const mesh::TriangleMesh& mesh, const Sample& sample) {
  if (sample.vertex) return glm::dvec3(glm::vec3(mesh.colours[*sample.vertex]));
  return colourAt(mesh, sample.triangle, sample.weights);
}

// Diagonal of the bounding box of the vertices the triangles use.
double usedDiagonal(const mesh::TriangleMesh& mesh, const std::vector<std::uint32_t>& usedVertices) {
  std::vector<glm::vec3> used;
  used.reserve(usedVertices.size());
  for (std::uint32_t v : usedVertices) used.push_back(mesh.positions[v]);
  return mesh::boundingBoxDiagonal(used);
}

// What one chunk of samples adds up to.
struct ChunkSums {
  double maxDistanceSquared = 0.0;
  double distanceSquared = 0.0;
  double colourSquared = 0.0;
  bool missed = false;  // a sample found no closest point (Embree gave no candidate)
};

Status checkMesh(const mesh::TriangleMesh& mesh, const char* what) {
  if (Status status = mesh::validateMesh(mesh, what); !status) return status;
  if (mesh.indices.empty()) {
    return makeError(ErrorKind::InvalidArgument,
                     std::string("measureSurfaceDeviation: the ") + what + " has no triangles");
  }
  return {};
}

}  // namespace

Result<SurfaceDeviation> measureSurfaceDeviation(const mesh::TriangleMesh& original,
                                                 const mesh::TriangleMesh& simplified,
                                                 const SurfaceDeviationOptions& options) {
  if (Status status = checkMesh(original, "original mesh"); !status) return status.error();
  if (Status status = checkMesh(simplified, "simplified mesh"); !status) return status.error();

  // Different streams: with equal meshes the two surfaces still get independent samples.
  const Surface surfaces[2] = {prepareSurface(original, options.samplesPerSurface, options.seed, 0),
                               prepareSurface(simplified, options.samplesPerSurface, options.seed, 1)};
  const double diagonal = usedDiagonal(original, surfaces[0].usedVertices);
  if (!(diagonal > 0.0)) {
    return makeError(ErrorKind::InvalidArgument,
                     "measureSurfaceDeviation: the original mesh's vertices all coincide (no extent to relate to)");
  }

  std::unique_ptr<detail::ClosestPointScene> scenes[2];
  for (int s = 0; s < 2; ++s) {
    auto scene =
        detail::ClosestPointScene::create(surfaces[s].mesh->positions, surfaces[s].mesh->indices, options.threads);
    if (!scene) return scene.error();
    scenes[s] = std::move(*scene);
  }

  // Samples of the original first (measured against the simplified mesh), then those of
  // the simplified mesh (measured against the original).
  const bool colours = original.hasColours() && simplified.hasColours();
  const std::size_t originalSamples = surfaces[0].sampleCount();
  const std::size_t totalSamples = originalSamples + surfaces[1].sampleCount();
  const std::size_t chunkCount = (totalSamples + kChunkSamples - 1) / kChunkSamples;
  std::vector<ChunkSums> chunks(chunkCount);
  auto measureChunks = [&](std::size_t firstChunk, std::size_t endChunk) {
    for (std::size_t chunk = firstChunk; chunk < endChunk; ++chunk) {
      ChunkSums sums;
      // The previous sample's closest point bounds this sample's distance (it lies on the
      // surface searched), and neighbouring samples are close, so the search starts small.
      // Reset per chunk so no result depends on which thread ran the chunk before.
      std::optional<glm::dvec3> previousClosest;
      int previousFrom = -1;
      const std::size_t end = std::min(totalSamples, (chunk + 1) * kChunkSamples);
      for (std::size_t i = chunk * kChunkSamples; i < end; ++i) {
        const int from = i < originalSamples ? 0 : 1;
        const Sample sample = sampleOf(surfaces[from], from == 0 ? i : i - originalSamples);
        const detail::ClosestPointScene& target = *scenes[1 - from];
        std::optional<detail::ClosestTriangle> closest;
        if (previousClosest && previousFrom == from) {
          closest = target.closest(sample.point, glm::length(sample.point - *previousClosest));
        }
        if (!closest) closest = target.closest(sample.point);
        if (!closest) {
          sums.missed = true;
          continue;
        }
        previousClosest = closest->closest.point;
        previousFrom = from;
        sums.maxDistanceSquared = std::max(sums.maxDistanceSquared, closest->distanceSquared);
        sums.distanceSquared += closest->distanceSquared;
        if (colours && from == 0) {
          const glm::dvec3 difference =
              colourAt(original, sample) - colourAt(simplified, closest->triangle, closest->closest.weights);
          sums.colourSquared += glm::dot(difference, difference);
        }
      }
      chunks[chunk] = sums;
    }
  };
  core::ThreadPool(options.threads).forRanges(chunkCount, 1, measureChunks);

  double maxDistanceSquared = 0.0, distanceSquared = 0.0, colourSquared = 0.0;
  for (const ChunkSums& sums : chunks) {
    if (sums.missed) {
      return makeError(ErrorKind::Environment, "measureSurfaceDeviation: Embree found no closest point for a sample");
    }
    maxDistanceSquared = std::max(maxDistanceSquared, sums.maxDistanceSquared);
    distanceSquared += sums.distanceSquared;
    colourSquared += sums.colourSquared;
  }
  SurfaceDeviation result;
  result.samples = totalSamples;
  result.hausdorff = std::sqrt(maxDistanceSquared) / diagonal;
  result.rms = std::sqrt(distanceSquared / double(totalSamples)) / diagonal;
  if (colours) result.colourRms = std::sqrt(colourSquared / double(originalSamples));
  return result;
}

}  // namespace polder::query
