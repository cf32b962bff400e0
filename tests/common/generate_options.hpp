// tests/common/generate_options.hpp: generator settings sized for the scenes of
// scene_builders.hpp, so a test's cloud takes milliseconds (needs sim).
#pragma once
#include <sim/generator.hpp>

namespace test_support {

/// A small orbit over basicScene's 200 m ground: 48 x 48 px, 12 views, 40 m up.
inline sim::GenerateOptions smallOrbit() {
    sim::GenerateOptions o;
    o.orbit.altitude_m = 40.0;
    o.orbit.overlap_m = 2.0;
    o.orbit.fov_deg = 20.0;
    o.orbit.xres = 48;
    o.orbit.yres = 48;
    o.orbit.views = 12;
    return o;
}

}  // namespace test_support
