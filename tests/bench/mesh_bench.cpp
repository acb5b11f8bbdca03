// `polder mesh`'s triangle efficiency at equal error: the uniform-error blocks-plus-dikes mesh
// (terrain/uniform_mesh.hpp) against Martini's RTIN made strict, on a crop of a real DEM.
//
//   mesh_bench [DEM] [--crop N] [--errors 2,5,10] [--blocks 33] [--json PATH] [--write-crop PATH]
//
// DEM defaults to POLDER_SHARED_DATA_DIR/dems/mt_rainier_90m_srtm3.tif, cropped to N x N
// samples (default 513, a power of two plus one as Martini needs) around its centre. Per
// bound: our triangles (dikes included), time and measured max error; strict Martini's
// triangles (the largest Martini threshold whose true max error, measured exactly like ours
// against the full-resolution surface, is within the bound, found by binary search over its
// distinct vertex errors) and our ratio to it (target <= 1.1); and the ratio to Delatin's
// greedy Delaunay at the same bound, from reference counts (below). --write-crop writes the
// crop as little-endian float32, rows north first (an image's order), for
// tests/bench/mesh_reference.mjs, which runs the npm packages on it.
//
// Martini: V. Agafonkin, "Martini: real-time RTIN terrain mesh" (2019; npm @mapbox/martini),
// after W. Evans, D. Kirkpatrick, G. Townsend, "Right-triangulated irregular networks",
// Algorithmica 2001. Its error per vertex is the height difference at the hypotenuse midpoint
// only, folded up the bintree; the mesh splits a triangle while its midpoint's error exceeds
// the threshold. Implemented here in its image orientation (row 0 north).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <polder/terrain/dem_reader.hpp>
#include <polder/terrain/dike_errors.hpp>
#include <polder/terrain/dikes.hpp>
#include <polder/terrain/heightfield_crop.hpp>
#include <polder/terrain/uniform_mesh.hpp>

#ifndef POLDER_SHARED_DATA_DIR
#define POLDER_SHARED_DATA_DIR ""
#endif

namespace {

using polder::terrain::DikeVertex;
using polder::terrain::Heightfield;
using Clock = std::chrono::steady_clock;

constexpr double kMartiniTarget = 1.1;

// Delatin's strict triangle counts at 2, 5 and 10 m on the default crop (513 x 513 around the
// centre of mt_rainier_90m_srtm3.tif): npm `delatin` (V. Agafonkin; greedy insertion Delaunay
// after M. Garland, P. Heckbert, "Fast polygonal approximation of terrains and height fields",
// 1995). `issue`: the figures given with the request for this benchmark (their crop may sit a
// sample or so away from ours: their strict Martini counts are 425,122 / 353,941 / 262,813,
// ours, here and from npm @mapbox/martini 0.2.0 alike, 424,672 / 353,202 / 261,867); `rerun`:
// npm delatin 0.2.0 on mesh_bench's own crop through mesh_reference.mjs. Used only for the
// default crop and bounds.
struct DelatinReference {
  double errorM;
  std::size_t issue;
  std::size_t rerun;
};
constexpr DelatinReference kDelatinReference[] = {{2.0, 331466, 330819}, {5.0, 190465, 188956}, {10.0, 98733, 96857}};

[[noreturn]] void fail(const std::string& message) {
  std::fprintf(stderr, "mesh_bench: %s\n", message.c_str());
  std::exit(1);
}

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::vector<double> parseList(const std::string& text) {
  std::vector<double> values;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    values.push_back(std::stod(text.substr(start, comma - start)));
    start = comma + 1;
  }
  return values;
}

// Martini's error hierarchy over a (2^k + 1)^2 field, in image coordinates (row r = north to
// south) as the npm package sees an image: (x, r) is sample (x, size - 1 - r).
class Martini {
 public:
  explicit Martini(const Heightfield& field)
      : m_field(field), m_size(field.width), m_errors(std::size_t(m_size) * m_size, 0.0f) {
    const int tile = m_size - 1;
    const std::size_t smallest = std::size_t(tile) * tile;
    const std::size_t count = smallest * 2 - 2, parents = count - smallest;
    for (std::size_t i = count; i-- > 0;) {
      std::size_t id = i + 2;
      int ax = 0, ay = 0, bx = 0, by = 0, cx = 0, cy = 0;
      if (id & 1) {
        bx = by = cx = tile;
      } else {
        ax = ay = cy = tile;
      }
      while ((id >>= 1) > 1) {
        const int mx = (ax + bx) >> 1, my = (ay + by) >> 1;
        if (id & 1) {
          bx = ax, by = ay;
          ax = cx, ay = cy;
        } else {
          ax = bx, ay = by;
          bx = cx, by = cy;
        }
        cx = mx, cy = my;
      }
      const int mx = (ax + bx) >> 1, my = (ay + by) >> 1;
      const float interpolated = (height(ax, ay) + height(bx, by)) / 2.0f;
      float& error = m_errors[index(mx, my)];
      error = std::max(error, std::fabs(interpolated - height(mx, my)));
      if (i < parents) {
        error = std::max(
            {error, m_errors[index((ax + cx) >> 1, (ay + cy) >> 1)], m_errors[index((bx + cx) >> 1, (by + cy) >> 1)]});
      }
    }
  }

  // The distinct vertex errors, ascending: the thresholds where the mesh changes.
  std::vector<float> thresholds() const {
    std::vector<float> values(m_errors);
    std::sort(values.begin(), values.end());
    values.erase(std::unique(values.begin(), values.end()), values.end());
    return values;
  }

  // The mesh at `threshold` (as the package's getMesh): triangles in global sample coordinates.
  std::vector<DikeVertex> mesh(float threshold) const {
    std::vector<DikeVertex> out;
    const int tile = m_size - 1;
    split(0, 0, tile, tile, tile, 0, threshold, out);
    split(tile, tile, 0, 0, 0, tile, threshold, out);
    return out;
  }

  // The max error of a mesh: exact against the full-resolution surface, like ours, or at the
  // samples only (what the npm packages measure).
  float maxError(const std::vector<DikeVertex>& triangles, bool samplesOnly) const {
    float worst = 0.0f;
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
      const DikeVertex &a = triangles[t], &b = triangles[t + 1], &c = triangles[t + 2];
      worst = std::max(worst, samplesOnly ? polder::terrain::triangleSampleError(m_field, a, b, c)
                                          : polder::terrain::dikeTriangleError(m_field, a, b, c));
    }
    return worst;
  }

 private:
  std::size_t index(int x, int r) const { return std::size_t(r) * m_size + x; }
  float height(int x, int r) const { return m_field.at(x, m_size - 1 - r); }
  void split(int ax, int ay, int bx, int by, int cx, int cy, float threshold, std::vector<DikeVertex>& out) const {
    const int mx = (ax + bx) >> 1, my = (ay + by) >> 1;
    if (std::abs(ax - cx) + std::abs(ay - cy) > 1 && m_errors[index(mx, my)] > threshold) {
      split(cx, cy, ax, ay, mx, my, threshold, out);
      split(bx, by, cx, cy, mx, my, threshold, out);
      return;
    }
    for (const auto& [x, r] : {std::pair{ax, ay}, std::pair{bx, by}, std::pair{cx, cy}})
      out.push_back(DikeVertex{x, m_size - 1 - r});
  }

  const Heightfield& m_field;
  int m_size;
  std::vector<float> m_errors;
};

struct StrictMartini {
  float threshold = -1.0f;  // -1: even the full-detail mesh misses the bound
  std::size_t triangles = 0;
  float maxErrorM = 0.0f;
  bool reachable = false;
};

// The largest threshold whose true max error is within the bound (binary search: the meshes
// are nested, so their error falls with the threshold, up to the rounding of a few planes).
StrictMartini strictMartini(const Martini& martini, const std::vector<float>& thresholds, double bound,
                            bool samplesOnly) {
  StrictMartini best;
  const std::vector<DikeVertex> full = martini.mesh(-1.0f);
  best.triangles = full.size() / 3;
  best.maxErrorM = martini.maxError(full, samplesOnly);
  best.reachable = best.maxErrorM <= bound;
  if (!best.reachable) return best;
  std::size_t lo = 0, hi = thresholds.size();  // thresholds[lo..hi) untested; below lo pass
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    const std::vector<DikeVertex> mesh = martini.mesh(thresholds[mid]);
    const float error = martini.maxError(mesh, samplesOnly);
    if (error <= bound) {
      best = StrictMartini{thresholds[mid], mesh.size() / 3, error, true};
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path demPath = std::filesystem::path(POLDER_SHARED_DATA_DIR) / "dems" / "mt_rainier_90m_srtm3.tif";
  int crop = 513;
  std::vector<double> bounds = {2.0, 5.0, 10.0};
  std::vector<double> blocks = {33};
  std::string jsonPath, cropPath;
  bool explicitDem = false;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    auto next = [&]() -> std::string {
      if (a + 1 >= argc) fail(arg + " needs a value");
      return argv[++a];
    };
    if (arg == "--crop")
      crop = std::stoi(next());
    else if (arg == "--errors")
      bounds = parseList(next());
    else if (arg == "--blocks")
      blocks = parseList(next());
    else if (arg == "--json")
      jsonPath = next();
    else if (arg == "--write-crop")
      cropPath = next();
    else if (arg.rfind("--benchmark", 0) == 0)
      continue;  // `./run bench` passes Google Benchmark's options to all
    else if (!arg.empty() && arg[0] != '-')
      demPath = arg, explicitDem = true;
    else
      fail("unknown option " + arg);
  }
  if (crop < 3 || ((crop - 1) & (crop - 2)) != 0) fail("--crop must be 2^k + 1 (Martini's grid)");
  if (!explicitDem && !std::filesystem::exists(demPath)) {
    std::printf("mesh_bench: %s is absent (the shared data folder); skipped\n", demPath.string().c_str());
    return 0;
  }
  auto dem = polder::terrain::readDem(demPath);
  if (!dem) fail(dem.error().message);
  auto cropped = polder::terrain::cropCentre(dem->field, crop, crop);
  if (!cropped) fail(cropped.error().message);
  const Heightfield& field = *cropped;
  const bool defaultCrop = demPath.filename() == "mt_rainier_90m_srtm3.tif" && crop == 513;
  std::printf("%s, %d x %d at the centre (spacing %.2f x %.2f m), %zu full-resolution triangles\n",
              demPath.string().c_str(), crop, crop, field.spacingX, field.spacingY,
              std::size_t(2) * (crop - 1) * (crop - 1));

  if (!cropPath.empty()) {
    std::ofstream out(cropPath, std::ios::binary);
    for (int r = 0; r < crop; ++r)
      for (int x = 0; x < crop; ++x) {
        const float h = field.at(x, crop - 1 - r);
        out.write(reinterpret_cast<const char*>(&h), sizeof h);  // little-endian machines only
      }
    if (!out) fail("cannot write " + cropPath);
    std::printf("crop written to %s (float32, rows north first)\n", cropPath.c_str());
  }

  const Martini martini(field);
  const std::vector<float> thresholds = martini.thresholds();
  nlohmann::json report = {{"dem", demPath.string()}, {"crop", crop}, {"rows", nlohmann::json::array()}};
  std::printf("\n%7s %6s %9s %8s %8s %7s | %9s %9s %8s | %9s %8s | %8s %8s\n", "bound_m", "block", "ours", "dikes",
              "error_m", "time_s", "martini", "m_exact", "/martini", "m_samples", "/m_samp", "delatin", "/delatin");
  bool allMet = true;
  for (const double bound : bounds) {
    const StrictMartini exact = strictMartini(martini, thresholds, bound, false);
    const StrictMartini samples = strictMartini(martini, thresholds, bound, true);
    std::size_t delatin = 0, delatinIssue = 0;
    for (const DelatinReference& reference : kDelatinReference)
      if (defaultCrop && reference.errorM == bound) delatin = reference.rerun, delatinIssue = reference.issue;
    for (const double block : blocks) {
      polder::terrain::UniformMeshOptions options;
      options.maxErrorM = bound;
      options.blockK = int(std::lround(std::log2(block - 1)));
      const auto start = Clock::now();
      auto mesh = polder::terrain::buildUniformMesh(field, options);
      const double seconds = secondsSince(start);
      if (!mesh) fail(mesh.error().message);
      const double triangles = double(mesh->triangleCount());
      const double exactRatio = exact.reachable ? triangles / double(exact.triangles) : 0.0;
      const double samplesRatio = triangles / double(samples.triangles);
      const double delatinRatio = delatin ? triangles / double(delatin) : 0.0;
      // Strict Martini by our measure, or where even its full mesh misses the bound there (its
      // half cells cut across the surface's diagonals), by its own, which is easier to meet.
      allMet &= (exact.reachable ? exactRatio : samplesRatio) <= kMartiniTarget;
      std::printf("%7.2f %6d %9zu %8zu %8.4f %7.3f | %9s %9.4f %8s | %9zu %8.3f | %8zu %8.3f\n", bound, int(block),
                  mesh->triangleCount(), mesh->stats.dikeTriangles, mesh->maxErrorM(), seconds,
                  exact.reachable ? std::to_string(exact.triangles).c_str() : "none", exact.maxErrorM,
                  exact.reachable ? std::to_string(exactRatio).substr(0, 5).c_str() : "-", samples.triangles,
                  samplesRatio, delatin, delatinRatio);
      std::string levels;
      for (std::size_t l = 0; l < mesh->stats.nodesPerLevel.size(); ++l)
        levels += std::string(l ? "," : "") + std::to_string(mesh->stats.nodesPerLevel[l]);
      std::printf("        nodes per level %s; %zu pinned, %zu split, %zu rounds\n", levels.c_str(),
                  mesh->stats.pinnedNodes, mesh->stats.splitNodes, mesh->stats.rounds);
      report["rows"].push_back({{"bound_m", bound},
                                {"block", int(block)},
                                {"triangles", mesh->triangleCount()},
                                {"dike_triangles", mesh->stats.dikeTriangles},
                                {"max_error_m", mesh->maxErrorM()},
                                {"seconds", seconds},
                                {"martini_exact_reachable", exact.reachable},
                                {"martini_exact_triangles", exact.triangles},
                                {"martini_exact_max_error_m", exact.maxErrorM},
                                {"martini_samples_triangles", samples.triangles},
                                {"martini_samples_threshold_m", samples.threshold},
                                {"ratio_to_martini_exact", exactRatio},
                                {"ratio_to_martini_samples", samplesRatio},
                                {"delatin_rerun_triangles", delatin},
                                {"delatin_issue_triangles", delatinIssue},
                                {"ratio_to_delatin_issue", delatinIssue ? triangles / double(delatinIssue) : 0.0},
                                {"ratio_to_delatin", delatinRatio}});
    }
  }
  std::printf(
      "\nmartini: strict by our exact measure (none: its full-detail mesh, m_exact, misses the bound);\n"
      "m_samples: strict by the samples only, the packages' own measure, which ours always meets too\n");
  std::printf("target: ours / strict Martini <= %.2f (exact where reachable, else samples): %s\n", kMartiniTarget,
              allMet ? "met" : "MISSED");
  if (defaultCrop)
    std::printf(
        "delatin: npm delatin 0.2.0 on this crop (mesh_reference.mjs), a reference figure, not run here; the\n"
        "issue's figures for its crop: 331,466 / 190,465 / 98,733 at 2 / 5 / 10 m\n");
  if (!jsonPath.empty()) {
    std::ofstream out(jsonPath);
    out << report.dump(2) << "\n";
  }
  return 0;
}
