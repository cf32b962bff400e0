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

/// One nadir view from 100 m over the world origin (alpha 0, CO 0: the drone sits above
/// the origin), 64 x 64 px, white: for sensor tests on known geometry.
inline sim::GenerateOptions nadirView() {
    sim::GenerateOptions o;
    o.orbit.altitude_m = 100.0;
    o.orbit.inclination_deg = 0.0;
    o.orbit.overlap_m = 0.0;
    o.orbit.xres = 64;
    o.orbit.yres = 64;
    o.orbit.views = 1;
    o.centre = glm::dvec3(0.0);
    o.white = true;
    return o;
}

}  // namespace test_support
