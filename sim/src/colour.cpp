// sim/colour.cpp: the jet colour map with 64 values, red low, blue high (paper §III-C);
// the table and the height-to-entry rule live in core/jet.hpp, shared with the viewer.
#include <sim/colour.hpp>

#include <core/error.hpp>
#include <core/jet.hpp>

#include <string>

namespace sim {

void validate(const ColourOptions& o) {
    if (o.entries < 2 || o.entries > 256)
        throw core::Error("colour: entries (--colours) = " + std::to_string(o.entries) + ": allowed [2, 256]");
}

std::uint32_t heightColour(float z, float z_min, float z_max, const std::vector<std::uint32_t>& jet) {
    return jet[core::jetIndex(z, z_min, z_max, int(jet.size()))];
}

}  // namespace sim
