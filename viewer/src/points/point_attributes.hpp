// viewer/src/points/point_attributes.hpp: what the viewer's class, intensity and return
// colours need of each point (its ASPRS class, its intensity stretched to 8 bits, its
// return number and its pulse's number of returns), packed into the 4 bytes its GPU record
// keeps for the height above ground on clouds that hold none: the record's size stays the
// same for every cloud.
#pragma once
#include <core/point_cloud.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace viewer {

/// The packed word: bits 0-7 the class, 8-15 the stretched intensity, 16-18 the return
/// number, 19-21 the number of returns (both capped at 7). Below 2^22, so a float holds it
/// exactly (shaders/include/viewer_point_style.glsl reads it back).
std::uint32_t packAttributes(std::uint8_t cls, std::uint8_t intensity, unsigned return_number, unsigned returns);
/// The class of a packed word as a point record holds it (a float of its value).
std::uint8_t classOfPacked(float packed);
/// The class our LAS writer gives a label (io::WriteOptions::class_of_role's default):
/// ground 2, environment 1, target 64.
std::uint8_t classOfLabel(core::Role label);

/// The intensities' 2nd and 98th percentiles, mapped to 0 and 255 (values between
/// linearly, beyond clamped); a stretch with hi <= lo maps lo and below to 0, the rest to 255.
struct IntensityStretch {
    double lo = 0.0, hi = 65535.0;
    std::uint8_t apply(std::uint16_t intensity) const;
    /// The percentiles of `points`' intensities (none for no points).
    static std::optional<IntensityStretch> of(std::span<const core::CloudPoint> points);
};

/// Packs a cloud's points chunk by chunk as they are read.
class PointAttributes {
  public:
    /// `stretch`: the intensities' stretch, when one was chosen already (else the first
    /// chunk's).
    explicit PointAttributes(std::optional<IntensityStretch> stretch = std::nullopt) : stretch_(stretch) {}
    /// Writes each point's packed word (as a float) into its height_above_ground_m. The
    /// class is its side record's (`records`, `stride` bytes each, a core::ForeignPoint
    /// first; stride 0: none) where there is one, else classOfLabel. The stretch is taken
    /// from the first chunk packed that has points and kept for the rest.
    void pack(std::span<core::CloudPoint> points, std::span<const unsigned char> records = {}, std::size_t stride = 0);
    const std::optional<IntensityStretch>& stretch() const { return stretch_; }

  private:
    std::optional<IntensityStretch> stretch_;
};

}  // namespace viewer
