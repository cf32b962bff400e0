// cloud_units: detection in metres on a survey in other units (detect/cloud_units.hpp).
#include <core/error.hpp>
#include <detect/cloud_units.hpp>

#include <cmath>

namespace detect {
namespace {

glm::dvec3 unitLengths_m(const sim::CoordinateUnits& u) { return {u.horizontal_m, u.horizontal_m, u.vertical_m}; }

// The same length to within rounding: the units a CRS gives are read again from the same file.
bool sameLength(double a_m, double b_m) { return std::abs(a_m - b_m) <= 1e-9 * std::max(a_m, b_m); }

std::string unitWords(double horizontal_m, double vertical_m) {
    sim::CoordinateUnits u;
    u.horizontal_m = horizontal_m;
    u.vertical_m = vertical_m;
    if (u.metres()) return "metres";
    return "units of " + core::shownNumber(horizontal_m) + " m" +
           (sameLength(horizontal_m, vertical_m) ? std::string() : " and " + core::shownNumber(vertical_m) + " m (z)");
}

}  // namespace

void scaleToMetres(core::PointCloud& cloud, const sim::CoordinateUnits& u) {
    if (u.metres()) return;
    const glm::vec3 k(unitLengths_m(u));
    for (core::CloudPoint& p : cloud.points) p.position *= k;
}

std::vector<core::Candidate> centresInUnits(std::vector<core::Candidate> found, const glm::dvec3& origin,
                                            const sim::CoordinateUnits& u) {
    if (u.metres()) return found;
    const glm::dvec3 k = unitLengths_m(u);
    for (core::Candidate& c : found) c.centre_world = origin + (c.centre_world - origin) / k;
    return found;
}

io::CandidateUnits candidateUnits(const sim::CoordinateUnits& u) {
    io::CandidateUnits out;
    out.horizontal_m = u.horizontal_m;
    out.vertical_m = u.vertical_m;
    return out;
}

std::vector<core::Candidate> sizesInCloudUnits(std::vector<core::Candidate> candidates, const io::CandidateUnits& file,
                                               const sim::CoordinateUnits& cloud, const std::string& name) {
    if (!sameLength(file.horizontal_m, cloud.horizontal_m) || !sameLength(file.vertical_m, cloud.vertical_m))
        throw core::Error(name + ": centres in " + unitWords(file.horizontal_m, file.vertical_m) +
                          "; the cloud is in " + sim::describe(cloud) +
                          ": allowed candidates found in this cloud (`ladarvr detect` on it)");
    if (cloud.metres()) return candidates;
    const glm::dvec3 k = unitLengths_m(cloud);
    for (core::Candidate& c : candidates) c.size_m /= k;
    return candidates;
}

}  // namespace detect
