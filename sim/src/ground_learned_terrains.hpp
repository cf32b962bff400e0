// sim/src/ground_learned_terrains.hpp: what the learned refinement of SMRF
// (ground_learned.cpp) takes from SMRF's fit (ground_smrf.cpp): besides SMRF's own
// terrain, the terrains of a few other slopes and windows made from the same openings of
// the same ground-level surface, and that surface itself.
#pragma once
#include <sim/ground.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace sim {

/// Another SMRF setting whose terrain the fit also makes (no raised segments).
struct SmrfVariant {
    double slope = 0.15;
    double window_m = 18.0;
};

/// SMRF's fit with its variants' terrains. After fit(): variant(k) has surface()'s
/// geometry; levels() is the ground-level surface (kNoPoint where no point fell), one
/// value per cell of surface(); limit(c) the ground tolerance of cell c.
class SmrfTerrains : public TerrainFit {
  public:
    virtual const TerrainGrid& variant(std::size_t k) const = 0;
    virtual const std::vector<float>& levels() const = 0;
    virtual float limit(std::size_t cell) const = 0;
};

/// SMRF (validate(o) passed) with the terrains of `variants` too.
std::unique_ptr<SmrfTerrains> startSmrfTerrains(const SmrfOptions& o, const std::vector<SmrfVariant>& variants);

}  // namespace sim
