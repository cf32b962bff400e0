// detect/cloud_units.hpp: a detector's lengths are metres (target sizes, voxels, join
// distances, the trained model's features), so a survey whose coordinates are in other
// units (US survey feet, sim/ground_units.hpp) is detected in metres: its local
// coordinates are scaled, its origin kept, and each candidate's centre is put back in the
// survey's own coordinates, where the viewer draws it. Sizes stay in metres.
#pragma once
#include <core/candidates.hpp>
#include <core/point_cloud.hpp>
#include <io/candidates_file.hpp>
#include <sim/ground_units.hpp>

#include <string>
#include <vector>

namespace detect {

/// `cloud` with its local coordinates (each point's offset from its origin) in metres:
/// x and y times u.horizontal_m, z times u.vertical_m. The origin is kept, so a world
/// position of the result is not a position in any CRS until centresInUnits turns it back.
void scaleToMetres(core::PointCloud& cloud, const sim::CoordinateUnits& u);

/// `found`, detected in a cloud scaleToMetres turned, with each centre back in the
/// survey's coordinates: origin + (centre - origin) / unit, per axis. Sizes and yaw are
/// kept (a scale alike in x and y keeps every angle).
std::vector<core::Candidate> centresInUnits(std::vector<core::Candidate> found, const glm::dvec3& origin,
                                            const sim::CoordinateUnits& u);

/// The units a candidates file records for centres in `u`.
io::CandidateUnits candidateUnits(const sim::CoordinateUnits& u);

/// `candidates` from a file whose centres are in `file` units, ready to draw over a cloud
/// whose coordinates are in `cloud` units: their sizes turned from metres into the cloud's
/// units. Throws core::Error("<name>: centres in <units>; the cloud is in <units>:
/// allowed candidates found in this cloud (`ladarvr detect` on it)") when the two differ:
/// a centre in other units would stand elsewhere.
std::vector<core::Candidate> sizesInCloudUnits(std::vector<core::Candidate> candidates, const io::CandidateUnits& file,
                                               const sim::CoordinateUnits& cloud, const std::string& name);

}  // namespace detect
