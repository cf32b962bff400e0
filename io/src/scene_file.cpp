// scene: roles, and loading a JSON scene file whose meshes Assimp reads.
// Every problem with a scene becomes one Error line naming the scene file, the mesh
// entry and what is allowed (see docs/scene.md for the list).
#include <core/error.hpp>
#include <io/scene_file.hpp>
#include <io/strict_json.hpp>
#include <platform/safe_file.hpp>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <system_error>

namespace io {

using core::Error;
using core::kMaxLocalCoordinate_m;
using core::kMaxWorldCoordinate_m;
using core::kRoleCount;
using core::kRoleList;
using core::Mesh;
using core::parseRole;
using core::Role;
using core::roleName;
using core::Scene;
using core::shownNumber;
using platform::checkInputFile;
using platform::readTextFile;

namespace {

using nlohmann::json;

// One mesh file as read (file coordinates, before the entry's transform).
struct RawMesh {
    std::vector<glm::dvec3> vertices;
    std::vector<glm::uvec3> triangles;
    std::size_t nonfinite_triangles = 0;  // dropped (skip_nonfinite only)
};

using Entry = core::SceneEntry;

// The mesh file of an entry of the scene file `file`: its name as written, relative to the
// scene file's folder.
std::filesystem::path meshFile(const std::filesystem::path& file, const std::string& written) {
    return (file.parent_path() / written).lexically_normal();
}

double finiteNumber(const json& v, const std::string& where, const std::string& key, const std::string& allowed) {
    if (!v.is_number()) throw Error(where + ": '" + key + "' must be " + allowed + ", not " + jsonTypeName(v));
    const double d = v.get<double>();
    if (!std::isfinite(d)) throw Error(where + ": '" + key + "' is not finite; allowed: " + allowed);
    return d;
}

glm::dvec3 vec3Field(const json& v, const std::string& where, const std::string& key) {
    if (!v.is_array() || v.size() != 3)
        throw Error(where + ": '" + key + "' must be an array of 3 finite numbers [x, y, z] (metres)");
    glm::dvec3 out;
    for (int i = 0; i < 3; ++i) {
        if (!v[i].is_number())
            throw Error(where + ": '" + key +
                        "' must be an array of 3 finite numbers [x, y, z] "
                        "(metres); element " +
                        std::to_string(i) + " is " + jsonTypeName(v[i]));
        out[i] = v[i].get<double>();
        if (!std::isfinite(out[i]))
            throw Error(where + ": '" + key + "' element " + std::to_string(i) +
                        " is not finite; allowed: finite numbers (metres)");
        if (std::abs(out[i]) > kMaxWorldCoordinate_m)
            throw Error(where + ": '" + key + "' element " + std::to_string(i) + " is " + shownNumber(out[i]) +
                        "; allowed: [-" + shownNumber(kMaxWorldCoordinate_m) + ", " +
                        shownNumber(kMaxWorldCoordinate_m) + "] (world metres)");
    }
    return out;
}

Entry parseEntry(const json& j, const std::string& scene_name, std::size_t index) {
    std::string where = scene_name + ": meshes[" + std::to_string(index) + "]";
    if (!j.is_object())
        throw Error(where + ": a mesh entry must be a JSON object with 'file' and 'role', not " + jsonTypeName(j));
    Entry e;
    // 'file' first so every later message can name it.
    const auto file_it = j.find("file");
    if (file_it == j.end()) throw Error(where + ": 'file' is missing; it names a mesh file relative to the scene file");
    if (!file_it->is_string())
        throw Error(where +
                    ": 'file' must be a non-empty string (a mesh file relative to the "
                    "scene file), not " +
                    jsonTypeName(*file_it));
    if (file_it->get<std::string>().empty())
        throw Error(where +
                    ": 'file' is an empty string; allowed: a mesh file name relative to "
                    "the scene file");
    e.file = file_it->get<std::string>();
    where += " ('" + core::printable(e.file, 120, true) + "')";

    for (auto it = j.begin(); it != j.end(); ++it) {
        const std::string& key = it.key();
        const json& v = it.value();
        if (key == "file" || key == "comment") {
            if (key == "comment" && !v.is_string()) throw Error(where + ": 'comment' must be a string");
        } else if (key == "role") {
            if (!v.is_string()) throw Error(where + ": 'role' must be a string, one of " + std::string(kRoleList));
            e.role = parseRole(v.get<std::string>(), where);
        } else if (key == "position") {
            e.position = vec3Field(v, where, key);
        } else if (key == "yaw_deg") {
            e.yaw_deg = finiteNumber(v, where, key, "a finite number (degrees)");
        } else if (key == "pitch_deg" || key == "roll_deg") {
            const double a = finiteNumber(v, where, key, "a number in [-90, 90] (degrees)");
            if (!(a >= -90.0 && a <= 90.0))
                throw Error(where + ": '" + key + "' is " + shownNumber(a) +
                            "; allowed: a number in [-90, 90] (degrees)");
            (key == "pitch_deg" ? e.pitch_deg : e.roll_deg) = a;
        } else if (key == "scale") {
            e.scale = finiteNumber(v, where, key, "a finite number > 0");
            if (!(e.scale > 0.0))
                throw Error(where + ": 'scale' is " + shownNumber(e.scale) + "; allowed: a finite number > 0");
        } else if (key == "reflectance") {
            e.reflectance = finiteNumber(v, where, key, "a number in [0, 1]");
            if (!(e.reflectance >= 0.0 && e.reflectance <= 1.0))
                throw Error(where + ": 'reflectance' is " + shownNumber(e.reflectance) +
                            "; allowed: a number in [0, 1]");
        } else if (key == "up") {
            if (!v.is_string()) throw Error(where + ": 'up' must be the string \"y\" or \"z\", not " + jsonTypeName(v));
            const std::string up = v.get<std::string>();
            if (up != "y" && up != "z")
                throw Error(where + ": 'up' is '" + core::printable(up, 20, true) + "'; allowed: y, z");
            e.up_y = up == "y";
        } else if (key == "class") {
            if (!v.is_number_integer() || v.get<long long>() < 0 || v.get<long long>() > 255)
                throw Error(where + ": 'class' must be an ASPRS class, an integer in 0..255");
            e.asprs_class = int(v.get<long long>());
        } else {
            throw Error(where + ": unknown key '" + core::printable(key, 40, true) +
                        "'; allowed keys: file, role, position, yaw_deg, pitch_deg, roll_deg, scale, up, reflectance, "
                        "class, comment");
        }
    }
    if (j.find("role") == j.end()) throw Error(where + ": 'role' is missing; allowed: " + std::string(kRoleList));
    return e;
}

// Reads a mesh file with Assimp into file coordinates; all meshes of the file merged,
// node transforms applied (PreTransformVertices).
RawMesh importMesh(const std::filesystem::path& path, const std::string& where, bool skip_nonfinite) {
    namespace fs = std::filesystem;
    const std::string shown_path = core::printable(path.string(), 400, true);
    // A regular file (not a FIFO Assimp would block on, nor a device); sceneFiles names it
    // to the command, which keeps its outputs off it.
    checkInputFile(path, where + ": mesh file '" + shown_path + "'");
    {
        std::ifstream probe(path, std::ios::binary);
        if (!probe) throw Error(where + ": mesh file '" + shown_path + "' cannot be read");
    }
    Assimp::Importer importer;
    // Points and lines carry no surface: have Assimp drop them.
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    // Import without post-processing first: JoinIdenticalVertices would silently merge
    // NaN vertices away, and we want to reject them (or, with skip_nonfinite, keep them
    // apart so the triangles that use them can be dropped below).
    const aiScene* ai = importer.ReadFile(path.string(), 0);
    if (ai) {
        bool any_nonfinite = false;
        std::size_t index = 0;
        for (unsigned mi = 0; mi < ai->mNumMeshes; ++mi) {
            const aiMesh* m = ai->mMeshes[mi];
            if (!m || !m->mVertices) continue;
            for (unsigned vi = 0; vi < m->mNumVertices; ++vi, ++index) {
                const aiVector3D& v = m->mVertices[vi];
                if (std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) continue;
                any_nonfinite = true;
                if (!skip_nonfinite)
                    throw Error(where + ": mesh file '" + shown_path + "': vertex " + std::to_string(index) +
                                " is not finite (" + shownNumber(v.x) + ", " + shownNumber(v.y) + ", " +
                                shownNumber(v.z) + "); allowed: finite coordinates");
            }
        }
        unsigned steps = aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType;
        if (!any_nonfinite) steps |= aiProcess_JoinIdenticalVertices;
        ai = importer.ApplyPostProcessing(steps);
    }
    if (!ai) {
        std::string reason = importer.GetErrorString();
        for (char& c : reason)
            if (c == '\n' || c == '\r') c = ' ';
        reason = core::printable(reason, 300);
        throw Error(where + ": Assimp cannot import mesh file '" + shown_path + "': " + reason +
                    "; allowed: a triangle mesh in a format Assimp reads (OBJ, PLY, "
                    "glTF/GLB, AC3D, ...)");
    }
    RawMesh raw;
    for (unsigned mi = 0; mi < ai->mNumMeshes; ++mi) {
        const aiMesh* m = ai->mMeshes[mi];
        if (!m || !m->mVertices) continue;
        const std::size_t base = raw.vertices.size();
        std::vector<bool> bad(m->mNumVertices, false);
        for (unsigned vi = 0; vi < m->mNumVertices; ++vi) {
            const aiVector3D& v = m->mVertices[vi];
            if (std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) {
                raw.vertices.emplace_back(v.x, v.y, v.z);
                continue;
            }
            if (skip_nonfinite) {  // kept as an unused placeholder: its triangles go below
                bad[vi] = true;
                raw.vertices.emplace_back(0.0);
                continue;
            }
            // Node transforms applied by PreTransformVertices can still overflow.
            throw Error(where + ": mesh file '" + shown_path + "': vertex " + std::to_string(base + vi) +
                        " is not finite after the file's node transforms; allowed: finite "
                        "coordinates");
        }
        for (unsigned fi = 0; fi < m->mNumFaces; ++fi) {
            const aiFace& f = m->mFaces[fi];
            if (f.mNumIndices != 3) continue;
            if (f.mIndices[0] >= m->mNumVertices || f.mIndices[1] >= m->mNumVertices ||
                f.mIndices[2] >= m->mNumVertices)
                throw Error(where + ": mesh file '" + shown_path + "': face " + std::to_string(fi) +
                            " indexes a vertex that does not exist");
            if (bad[f.mIndices[0]] || bad[f.mIndices[1]] || bad[f.mIndices[2]]) {
                ++raw.nonfinite_triangles;
                continue;
            }
            raw.triangles.emplace_back(unsigned(base) + f.mIndices[0], unsigned(base) + f.mIndices[1],
                                       unsigned(base) + f.mIndices[2]);
        }
    }
    if (raw.triangles.empty())
        throw Error(where + ": mesh file '" + shown_path + "' contains no triangles" +
                    (raw.nonfinite_triangles ? " with finite vertices" : "") +
                    "; allowed: a mesh with at least one face");
    return raw;
}

}  // namespace

std::vector<glm::dvec3> loadMeshVertices(const std::filesystem::path& file, bool up_y, double scale,
                                         const std::string& where) {
    return loadMeshTriangles(file, up_y, scale, where).vertices;
}

MeshTriangles loadMeshTriangles(const std::filesystem::path& file, bool up_y, double scale, const std::string& where) {
    RawMesh raw = importMesh(file, where, false);
    MeshTriangles out;
    out.vertices.reserve(raw.vertices.size());
    // Through float, as loadScene's local frame holds them (the same numbers either way).
    for (const glm::dvec3& v : raw.vertices)
        out.vertices.emplace_back(glm::vec3(scale * (up_y ? glm::dvec3(v.x, -v.z, v.y) : v)));
    out.triangles = std::move(raw.triangles);
    return out;
}

Scene loadScene(const std::filesystem::path& file, const SceneLoadOptions& options) {
    namespace fs = std::filesystem;
    const std::string name = "scene: " + core::printable(file.string(), 400, true);
    // A folder that `scene from-cloud` wrote holds its scene file: the line names it.
    std::error_code ec;
    if (fs::is_directory(fs::symlink_status(file, ec)) &&
        fs::is_regular_file(fs::symlink_status(file / "scene.json", ec)))
        throw Error(name + ": is a folder; allowed a scene file (this folder's is " +
                    core::printable((file / "scene.json").string(), 400, true) + ")");
    const std::string text = readTextFile(file, kMaxSceneBytes, name + ": the scene file");
    return loadSceneJson(text, file, options);
}

Scene loadSceneJson(std::string_view json_text, const std::filesystem::path& file, const SceneLoadOptions& options) {
    namespace fs = std::filesystem;
    const std::string name = "scene: " + file.string();
    const json root = parseStrictJson(json_text, name);
    if (!root.is_object())
        throw Error(name + ": the top level must be a JSON object with 'meshes', not " + jsonTypeName(root));

    Scene scene;
    scene.source = file;
    bool has_origin = false;
    const json* meshes = nullptr;
    for (auto it = root.begin(); it != root.end(); ++it) {
        if (it.key() == "origin") {
            scene.origin = vec3Field(it.value(), name, "origin");
            scene.written_origin = scene.origin;
            has_origin = true;
        } else if (it.key() == "meshes") {
            meshes = &it.value();
        } else if (it.key() == "comment") {
            if (!it.value().is_string()) throw Error(name + ": 'comment' must be a string");
        } else {
            throw Error(name + ": unknown key '" + core::printable(it.key(), 40, true) +
                        "'; allowed keys: origin, meshes, comment");
        }
    }
    if (!meshes) throw Error(name + ": 'meshes' is missing; it must be an array of mesh entries");
    if (!meshes->is_array() || meshes->empty())
        throw Error(name + ": 'meshes' must be a non-empty array of mesh entries");

    std::vector<Entry> entries;
    entries.reserve(meshes->size());
    for (std::size_t i = 0; i < meshes->size(); ++i) entries.push_back(parseEntry((*meshes)[i], name, i));

    if (options.require_target) {
        bool any = false;
        for (const Entry& e : entries) any = any || e.role == Role::Target;
        if (!any) {
            // A folder `scene from-cloud` wrote holds its record beside the scene file.
            std::error_code ec;
            const bool from_cloud = fs::is_regular_file(fs::symlink_status(file.parent_path() / "from_cloud.json", ec));
            throw Error(
                name + ": no mesh has role 'target'; a scene needs at least one target mesh" +
                (from_cloud ? " (scene from-cloud made this one without --vehicle: give it a vehicle mesh)" : ""));
        }
    }
    if (!has_origin) scene.origin = entries.front().position;
    scene.entries = entries;

    // Files used by several entries (trees, houses) are imported once.
    std::map<fs::path, std::shared_ptr<const RawMesh>> cache;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const Entry& e = entries[i];
        if (!options.roles.has(e.role)) continue;
        const std::string where =
            name + ": meshes[" + std::to_string(i) + "] ('" + core::printable(e.file, 120, true) + "')";
        const fs::path mesh_path = meshFile(file, e.file);
        auto& slot = cache[mesh_path];
        if (!slot) slot = std::make_shared<const RawMesh>(importMesh(mesh_path, where, options.skip_nonfinite));
        const RawMesh& raw = *slot;
        scene.skipped_nonfinite_triangles += raw.nonfinite_triangles;

        const double yaw_rad = glm::radians(e.yaw_deg);
        const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
        const glm::dvec3 shift = e.position - scene.origin;
        Mesh mesh;
        mesh.name = e.file;
        mesh.role = e.role;
        mesh.reflectance = e.reflectance;
        mesh.asprs_class = e.asprs_class;
        mesh.position = e.position;
        mesh.vertices.reserve(raw.vertices.size());
        for (std::size_t vi = 0; vi < raw.vertices.size(); ++vi) {
            const glm::dvec3& v = raw.vertices[vi];
            const glm::dvec3 p =
                core::tilt(e.scale * (e.up_y ? glm::dvec3(v.x, -v.z, v.y) : v), e.pitch_deg, e.roll_deg);
            const glm::dvec3 local = shift + glm::dvec3(c * p.x - s * p.y, s * p.x + c * p.y, p.z);
            // Local coordinates are floats: far out they step by metres (core/frames.hpp).
            const double reach_m = std::max({std::abs(local.x), std::abs(local.y), std::abs(local.z)});
            if (!(reach_m <= kMaxLocalCoordinate_m))
                throw Error(where + ": vertex " + std::to_string(vi) + " lies " + shownNumber(reach_m) +
                            " m from the origin after the position/yaw/tilt/scale transform; allowed: within " +
                            shownNumber(kMaxLocalCoordinate_m) +
                            " m of the scene's origin (local "
                            "coordinates are floats; give 'origin' near the meshes)");
            mesh.vertices.push_back(glm::vec3(local));
        }
        mesh.triangles.reserve(raw.triangles.size());
        for (const glm::uvec3& t : raw.triangles) {
            const glm::dvec3 a(mesh.vertices[t.x]), b(mesh.vertices[t.y]), d(mesh.vertices[t.z]);
            const glm::dvec3 n = glm::cross(b - a, d - a);
            if (glm::dot(n, n) == 0.0) {
                ++scene.skipped_triangles;
                continue;
            }
            mesh.triangles.push_back(t);
        }
        if (mesh.triangles.empty())
            throw Error(where + ": all " + std::to_string(raw.triangles.size()) +
                        " triangles have zero area; allowed: a mesh with at least one proper "
                        "triangle");
        scene.meshes.push_back(std::move(mesh));
    }
    if (scene.meshes.empty())
        throw Error(name + ": no mesh has one of the selected roles; the file's roles are " + [&] {
            std::string roles;
            for (int r = 0; r < kRoleCount; ++r)
                for (const Entry& e : entries)
                    if (int(e.role) == r) {
                        roles += (roles.empty() ? "" : ", ") + std::string(roleName(e.role));
                        break;
                    }
            return roles;
        }());
    return scene;
}

std::vector<std::filesystem::path> sceneFiles(const Scene& scene, core::RoleMask roles) {
    std::vector<std::filesystem::path> files{scene.source};
    for (const Entry& e : scene.entries)
        if (roles.has(e.role)) files.push_back(meshFile(scene.source, e.file));
    return files;
}

std::filesystem::path demoScenePath() { return std::filesystem::path(LADARVR_ASSETS_DIR) / "demo" / "scene.json"; }

}  // namespace io
