// metric/src/clouds.cpp: P1, P2, P3 of paper §IV-B from a scene through sim's generator.
// "Firstly, we generate three white 3D point clouds with our process detailed in section
// III-B: P1 with only the mesh of the target, P2 with only the meshes of the environment
// ... without the ground and P3 the meshes of the target and the environment without the
// ground."
#include <metric/clouds.hpp>

#include <core/error.hpp>

namespace metric {

MetricClouds generateClouds(const core::Scene& scene, const sim::GenerateOptions& base) {
    if (!scene.hasRole(core::Role::Target))
        throw core::Error("metric: scene '" + scene.source.string() + "' has no target mesh");
    using core::Role;
    sim::GenerateOptions options = base;
    options.white = true;
    // One centre C for the three runs (the generator computes it on the whole scene anyway).
    if (!options.centre) options.centre = sim::defaultCentre(scene);
    MetricClouds clouds;
    options.roles = core::RoleMask::of({Role::Target});
    clouds.p1 = sim::generateCloud(scene, options);
    options.roles = core::RoleMask::of({Role::Environment});
    clouds.p2 = scene.hasRole(Role::Environment) ? sim::generateCloud(scene, options) : core::PointCloud{};
    clouds.p2.origin = scene.origin;
    options.roles = core::RoleMask::of({Role::Target, Role::Environment});
    clouds.p3 = sim::generateCloud(scene, options);
    return clouds;
}

}  // namespace metric
