// point_cloud: the fused cloud in memory.
#include <core/point_cloud.hpp>

namespace core {

Bounds PointCloud::bounds() const {
    Bounds b;
    for (const CloudPoint& p : points) b.extend(glm::dvec3(p.position));
    return b;
}

}  // namespace core
