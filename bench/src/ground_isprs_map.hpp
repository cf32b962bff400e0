// bench/src/ground_isprs_map.hpp: a picture of where a ground filter errs on the ISPRS
// samples (`bench ground-isprs --map`): each sample seen from above, its points grey where
// the filter agrees with the reference (light: bare earth, darker: object), red where it
// calls bare earth an object (type I), blue where it calls an object bare earth (type II),
// the errors drawn last and larger so that a thin line of them still shows; the panels
// side by side in one RGB image, each with the sample's number in its corner.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace core {
struct CloudPoint;
}

namespace bench {

/// An 8-bit RGB image, rows top first.
struct MapImage {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  // width * height * 3

    /// The colour at (x, y), x to the right, y down from the top row.
    const std::uint8_t* at(int x, int y) const {
        return rgb.data() + (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3;
    }
};

// The colours the picture uses (its caption in docs/ground.md names them).
inline constexpr std::uint8_t kMapBackground[3] = {255, 255, 255};
inline constexpr std::uint8_t kMapGroundRight[3] = {200, 200, 200};
inline constexpr std::uint8_t kMapObjectRight[3] = {120, 120, 120};
inline constexpr std::uint8_t kMapTypeI[3] = {215, 25, 28};
inline constexpr std::uint8_t kMapTypeII[3] = {30, 90, 230};
inline constexpr std::uint8_t kMapLabel[3] = {0, 0, 0};
inline constexpr std::uint8_t kMapFrame[3] = {160, 160, 160};

/// One sample from above (x to the right, y up), scaled to fit a square of `side_px`
/// pixels with its aspect kept and centred; `truth` and `found` hold one flag per point
/// (1 = bare earth). `label` (digits only; others are skipped) is drawn in the top-left
/// corner. Throws core::Error when the sizes differ or side_px is under 16.
MapImage renderErrorPanel(const std::vector<core::CloudPoint>& points, const std::vector<std::uint8_t>& truth,
                          const std::vector<std::uint8_t>& found, int side_px, std::string_view label);

/// The panels (all of one size) in rows of `columns`, `gap_px` of background between
/// them and around, a line of kMapFrame around each panel where there is a gap. Throws core::Error when there is none or their sizes differ.
MapImage mosaic(const std::vector<MapImage>& panels, int columns, int gap_px);

}  // namespace bench
