// What a simplification builder produces: the cluster tree of ASLOD
// (seeds/000_b38ee0937017652c.txt, section 2) as the ordered list of its joins. Each step
// gathers one or more still-active vertices onto a representative, itself an original
// vertex that stays active, so every level of detail uses original vertices only and one
// vertex table serves them all. A half-edge collapse is a step with one removed vertex;
// the cluster builder (seeds/002_d92600183c0e5cf1.txt, part A) removes several per step.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace polder::mesh {

struct SimplificationSteps {
  std::vector<std::uint32_t> representative;  // per step
  std::vector<std::uint32_t> removedBegin{0};  // per step + 1: offsets into removed
  std::vector<std::uint32_t> removed;          // vertices gathered by each step
  std::vector<float> error;                    // per step: object-space error after it (builder's estimate)

  std::size_t size() const { return representative.size(); }
  std::span<const std::uint32_t> removedBy(std::size_t step) const {
    return {removed.data() + removedBegin[step], removedBegin[step + 1] - removedBegin[step]};
  }
  void add(std::uint32_t rep, std::span<const std::uint32_t> gathered, float stepError) {
    representative.push_back(rep);
    removed.insert(removed.end(), gathered.begin(), gathered.end());
    removedBegin.push_back(static_cast<std::uint32_t>(removed.size()));
    error.push_back(stepError);
  }
};

}  // namespace polder::mesh
