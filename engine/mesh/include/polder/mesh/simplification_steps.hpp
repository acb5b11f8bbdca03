// What a simplification builder produces: the cluster tree of ASLOD
// (Schmalstieg and Fuhrmann 1999, section 2) as the ordered list of its joins. Each step
// gathers one or more still-active vertices onto a representative, itself an original
// vertex that stays active, so every level of detail uses original vertices only and one
// vertex table serves them all. A half-edge collapse is a step with one removed vertex;
// the cluster builder (Chuang 2001, part A) removes several per step.
// A removed vertex usually goes onto the representative; across a texture seam, where the
// surface's vertices are split in two, a step also moves the removed vertex's twin onto the
// representative's twin, so both sides of the seam change together and never part.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace polder::mesh {

struct SimplificationSteps {
  std::vector<std::uint32_t> representative;   // per step
  std::vector<std::uint32_t> removedBegin{0};  // per step + 1: offsets into removed
  std::vector<std::uint32_t> removed;          // vertices gathered by each step
  std::vector<std::uint32_t> onto;             // per removed vertex: the active vertex taking its place
  std::vector<float> error;                    // per step: object-space error after it (builder's estimate)

  std::size_t size() const { return representative.size(); }
  std::span<const std::uint32_t> removedBy(std::size_t step) const {
    return {removed.data() + removedBegin[step], removedBegin[step + 1] - removedBegin[step]};
  }
  std::span<const std::uint32_t> ontoBy(std::size_t step) const {
    return {onto.data() + removedBegin[step], removedBegin[step + 1] - removedBegin[step]};
  }
  // Empties the list, keeping its room.
  void clear() {
    representative.clear(), removed.clear(), onto.clear(), error.clear();
    removedBegin.assign(1, 0);
  }
  // Appends a copy of `from`'s step `step`.
  void addCopyOf(const SimplificationSteps& from, std::size_t step) {
    add(from.representative[step], from.removedBy(step), from.ontoBy(step), from.error[step]);
  }
  // A step moving every gathered vertex onto rep.
  void add(std::uint32_t rep, std::span<const std::uint32_t> gathered, float stepError) {
    onto.insert(onto.end(), gathered.size(), rep);
    addRemoved(rep, gathered, stepError);
  }
  // A step moving removedVertices[i] onto ontoVertices[i] (the first onto rep).
  void add(std::uint32_t rep, std::span<const std::uint32_t> removedVertices,
           std::span<const std::uint32_t> ontoVertices, float stepError) {
    onto.insert(onto.end(), ontoVertices.begin(), ontoVertices.end());
    addRemoved(rep, removedVertices, stepError);
  }

 private:
  void addRemoved(std::uint32_t rep, std::span<const std::uint32_t> gathered, float stepError) {
    representative.push_back(rep);
    removed.insert(removed.end(), gathered.begin(), gathered.end());
    removedBegin.push_back(static_cast<std::uint32_t>(removed.size()));
    error.push_back(stepError);
  }
};

}  // namespace polder::mesh
