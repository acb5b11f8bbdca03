// Void filling by pull-push (Gortler et al., "The Lumigraph", SIGGRAPH 1996, section 3.4):
// "pull" builds a pyramid of weighted means of the valid samples, halving the size each
// level; "push" fills each level's missing weight from the bilinear upsampling of the level
// above. Every void, however large, gets a value in O(samples) work, blended from the
// nearest valid data at the right scale. A few Gauss-Seidel sweeps over the voids then
// smooth the seam between the pyramid's averages and the valid samples at the void edges.
#include <polder/terrain/void_fill.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace polder::terrain {
namespace {

constexpr int kSmoothingSweeps = 8;

struct Level {
  int width = 0;
  int height = 0;
  std::vector<float> value;   // weighted mean of the valid samples below
  std::vector<float> weight;  // min(1, valid weight below): 1 means fully known
};

// One level up: each cell is the weighted mean of its (up to) 2x2 children.
// `childAt(x, y, value, weight)` reads a child.
template <class ChildAt>
Level pull(int width, int height, ChildAt childAt) {
  Level up;
  up.width = (width + 1) / 2;
  up.height = (height + 1) / 2;
  up.value.assign(std::size_t(up.width) * std::size_t(up.height), 0.0f);
  up.weight.assign(up.value.size(), 0.0f);
  for (int y = 0; y < up.height; ++y) {
    for (int x = 0; x < up.width; ++x) {
      float sumWeight = 0.0f, sumValue = 0.0f;
      for (int cy = 2 * y; cy < std::min(2 * y + 2, height); ++cy) {
        for (int cx = 2 * x; cx < std::min(2 * x + 2, width); ++cx) {
          float value = 0.0f, weight = 0.0f;
          childAt(cx, cy, value, weight);
          sumWeight += weight;
          sumValue += weight * value;
        }
      }
      const std::size_t i = std::size_t(y) * std::size_t(up.width) + std::size_t(x);
      up.value[i] = sumWeight > 0.0f ? sumValue / sumWeight : 0.0f;
      up.weight[i] = std::min(sumWeight, 1.0f);
    }
  }
  return up;
}

// The coarse level's value at fine sample (x, y), bilinear: sample centre x + 0.5 at fine
// resolution is x / 2 - 0.25 in coarse samples.
float upsample(const Level& coarse, int x, int y) {
  const float fx = float(x) * 0.5f - 0.25f, fy = float(y) * 0.5f - 0.25f;
  const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
  const float tx = fx - float(x0), ty = fy - float(y0);
  const int xa = std::clamp(x0, 0, coarse.width - 1), xb = std::clamp(x0 + 1, 0, coarse.width - 1);
  const int ya = std::clamp(y0, 0, coarse.height - 1), yb = std::clamp(y0 + 1, 0, coarse.height - 1);
  const auto at = [&](int cx, int cy) {
    return coarse.value[std::size_t(cy) * std::size_t(coarse.width) + std::size_t(cx)];
  };
  const float bottom = at(xa, ya) + (at(xb, ya) - at(xa, ya)) * tx;
  const float top = at(xa, yb) + (at(xb, yb) - at(xa, yb)) * tx;
  return bottom + (top - bottom) * ty;
}

}  // namespace

std::int64_t countVoids(const Heightfield& field) {
  return std::int64_t(std::count_if(field.heights.begin(), field.heights.end(), [](float h) { return std::isnan(h); }));
}

std::int64_t fillVoids(Heightfield& field) {
  const std::int64_t voids = countVoids(field);
  if (voids == 0 || voids == std::int64_t(field.sampleCount())) return voids;

  // Pull. Level 0 is the field itself (NaN = weight 0), so it costs no copy.
  std::vector<Level> levels;
  levels.push_back(pull(field.width, field.height, [&](int x, int y, float& value, float& weight) {
    const float h = field.heights[field.index(x, y)];
    const bool valid = !std::isnan(h);
    value = valid ? h : 0.0f;
    weight = valid ? 1.0f : 0.0f;
  }));
  while (levels.back().width > 1 || levels.back().height > 1) {
    const Level& below = levels.back();
    levels.push_back(pull(below.width, below.height, [&below](int x, int y, float& value, float& weight) {
      const std::size_t i = std::size_t(y) * std::size_t(below.width) + std::size_t(x);
      value = below.value[i];
      weight = below.weight[i];
    }));
  }

  // Push, top down: blend what each level lacks in weight from the (complete) level above.
  for (std::size_t l = levels.size() - 1; l-- > 0;) {
    Level& fine = levels[l];
    const Level& coarse = levels[l + 1];
    for (int y = 0; y < fine.height; ++y) {
      for (int x = 0; x < fine.width; ++x) {
        const std::size_t i = std::size_t(y) * std::size_t(fine.width) + std::size_t(x);
        const float w = fine.weight[i];
        if (w < 1.0f) fine.value[i] = w * fine.value[i] + (1.0f - w) * upsample(coarse, x, y);
      }
    }
  }
  std::vector<std::uint32_t> voidIndices;
  voidIndices.reserve(std::size_t(voids));
  for (int y = 0; y < field.height; ++y) {
    for (int x = 0; x < field.width; ++x) {
      float& h = field.heights[field.index(x, y)];
      if (!std::isnan(h)) continue;
      h = upsample(levels.front(), x, y);
      voidIndices.push_back(std::uint32_t(field.index(x, y)));
    }
  }
  levels.clear();

  // Smooth: each void becomes the mean of its 4 neighbours (valid or filled). The indices
  // are in row order, so the row start advances instead of dividing.
  const std::size_t width = std::size_t(field.width), count = field.sampleCount();
  constexpr float kInverse[5] = {0.0f, 1.0f, 1.0f / 2.0f, 1.0f / 3.0f, 1.0f / 4.0f};
  for (int sweep = 0; sweep < kSmoothingSweeps; ++sweep) {
    std::size_t rowStart = 0;
    for (std::uint32_t i : voidIndices) {
      while (i >= rowStart + width) rowStart += width;
      float sum = 0.0f;
      int n = 0;
      if (i > rowStart) sum += field.heights[i - 1], ++n;
      if (i + 1 < rowStart + width) sum += field.heights[i + 1], ++n;
      if (i >= width) sum += field.heights[i - width], ++n;
      if (i + width < count) sum += field.heights[i + width], ++n;
      field.heights[i] = sum * kInverse[n];
    }
  }
  return voids;
}

}  // namespace polder::terrain
