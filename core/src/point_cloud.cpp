// point_cloud: the fused cloud in memory.
#include <core/point_cloud.hpp>

namespace core {

Bounds PointCloud::bounds() const {
    Bounds b;
    for (const CloudPoint& p : points) b.extend(glm::dvec3(p.position));
    return b;
}

std::vector<std::string> fieldNames(const CloudFields& f) {
    std::vector<std::string> names = {"x", "y", "z"};
    const auto add = [&](bool on, const char* name) {
        if (on) names.emplace_back(name);
    };
    add(f.rgb, "rgb");
    add(f.label, "label");
    add(f.view, "view");
    add(f.range, "range");
    add(f.intensity, "intensity");
    add(f.returns, "returns");
    add(f.incidence, "incidence");
    add(f.scan_angle, "scan_angle");
    add(f.height_above_ground, "height_above_ground");
    return names;
}

}  // namespace core
