// sim/src/ground_raster.hpp: what the raster-based whole-cloud filters (SMRF, CSF)
// share: the lowest point of each cell gathered in pass 1 (sparse tiles, any order), the
// terrain raster, hole filling, and pass 2's test against a per-cell tolerance.
#pragma once
#include <sim/ground.hpp>

#include <cstdint>
#include <limits>
#include <span>
#include <unordered_map>
#include <vector>

namespace sim {

/// A cell of the minimum surface that no point fell in.
inline constexpr float kNoPoint = std::numeric_limits<float>::infinity();

/// Fills the cells of `z` (nx x ny, row-major) whose `known` is 0: rings of cells next to
/// filled ones take the mean of their filled 8-neighbours, then successive
/// over-relaxation moves the filled values towards the mean of their 4-neighbours (a
/// membrane held by the known cells). Deterministic. Nothing known: `z` is left alone.
void inpaint(std::vector<float>& z, const std::vector<std::uint8_t>& known, int nx, int ny);

class RasterFit : public TerrainFit {
  public:
    /// `cell_option` names the cell size in errors, e.g. "smrf cell_m (--smrf-cell-m)".
    RasterFit(double cell_m, std::size_t max_cells, const char* cell_option);
    void add(std::span<const core::CloudPoint> points) override;
    /// Builds the minimum surface over the cells the points touched, then fitTerrain().
    void fit() override;
    const TerrainGrid& surface() const override { return grid_; }
    /// Ground when |z - terrain (bilinear)| <= limit_m_ of the nearest cell.
    bool classify(const glm::vec3& p, float& height_m) const override;

  protected:
    /// `minimum` (grid_'s geometry, kNoPoint where no point fell) to grid_.z_m and
    /// limit_m_ (one tolerance per cell).
    virtual void fitTerrain(std::vector<float>& minimum, const std::vector<std::uint8_t>& observed) = 0;

    TerrainGrid grid_;
    std::vector<float> limit_m_;

  private:
    float* tileFor(int tx, int ty);

    double cell_m_, inv_cell_;
    std::size_t max_cells_;
    const char* cell_option_;
    std::unordered_map<std::uint64_t, std::uint32_t> tiles_;  // tile (tx, ty) -> its block in tile_data_
    std::vector<float> tile_data_;
    std::uint64_t last_key_ = 0;
    float* last_tile_ = nullptr;
    int ix_min_ = std::numeric_limits<int>::max(), ix_max_ = std::numeric_limits<int>::min();
    int iy_min_ = std::numeric_limits<int>::max(), iy_max_ = std::numeric_limits<int>::min();
};

/// Runs `fit` on points in memory: flags (1 = ground), optionally the surface and heights.
std::vector<std::uint8_t> classifyInMemory(TerrainFit& fit, std::span<const glm::vec3> points, TerrainGrid* surface,
                                           std::vector<float>* height_m);

}  // namespace sim
