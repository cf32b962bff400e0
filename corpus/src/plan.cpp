// corpus: planning one item. Every random value comes from its own key's stream
// (corpus/random.hpp), so the plan of item i depends on (seed, i) and the SPEC alone.
#include <corpus/plan.hpp>
#include <corpus/random.hpp>

#include <core/error.hpp>
#include <io/scene_file.hpp>
#include <platform/safe_file.hpp>
#include <sim/raycaster.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <iterator>
#include <cmath>
#include <numbers>

namespace corpus {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// Shortest text that reads back as the same double.
std::string exactNumber(double v) {
    char buffer[40];
    const auto r = std::to_chars(buffer, buffer + sizeof buffer, v);
    return std::string(buffer, r.ptr);
}

/// A target model's vertices in its own frame (scale and up applied, no yaw, no position);
/// `where` names it in messages (the SPEC key or the base scene's entry).
std::vector<glm::dvec3> loadModel(const fs::path& file, const std::string& up, double scale, const std::string& where) {
    return io::loadMeshVertices(file, up == "y", scale, where);
}

bool overlaps(const core::Bounds& a, const core::Bounds& b) {
    for (int k = 0; k < 3; ++k)
        if (a.hi[k] <= b.lo[k] || b.hi[k] <= a.lo[k]) return false;
    return true;
}

// Whether the box of one of `mesh`'s triangles (local frame) overlaps `box` (world).
bool trianglesOverlap(const core::Mesh& mesh, const glm::dvec3& origin, const core::Bounds& box) {
    for (const glm::uvec3& t : mesh.triangles) {
        core::Bounds b;
        for (int k = 0; k < 3; ++k) b.extend(origin + glm::dvec3(mesh.vertices[t[k]]));
        if (overlaps(box, b)) return true;
    }
    return false;
}

}  // namespace

std::string ItemPlan::sceneText(const fs::path& folder) const {
    json j;
    std::string replay = "ladarvr generate --scene scene.json";
    for (const std::string& a : generateArgs()) replay += " " + a;
    j["comment"] = "corpus item " + id + " (index " + std::to_string(index) + "); the cloud again: " + replay;
    if (origin) j["origin"] = {origin->x, origin->y, origin->z};
    json list = json::array();
    for (const MeshEntry& m : meshes) {
        std::string file = m.file.string();
        // Relative paths keep a corpus and its meshes movable together; a path that
        // would climb to the root stays absolute.
        if (!folder.empty() && std::next(m.file.begin()) != m.file.end() && std::next(folder.begin()) != folder.end() &&
            *std::next(m.file.begin()) == *std::next(folder.begin())) {
            const fs::path rel = m.file.lexically_relative(folder);
            if (!rel.empty()) file = rel.string();
        }
        json entry{{"file", file},         {"role", m.role},   {"position", {m.position.x, m.position.y, m.position.z}},
                   {"yaw_deg", m.yaw_deg}, {"scale", m.scale}, {"up", m.up}};
        // Written when they differ from the scene format's defaults (the same scene either way).
        if (m.pitch_deg != 0.0) entry["pitch_deg"] = m.pitch_deg;
        if (m.roll_deg != 0.0) entry["roll_deg"] = m.roll_deg;
        if (m.reflectance != core::kDefaultReflectance) entry["reflectance"] = m.reflectance;
        if (m.asprs_class >= 0) entry["class"] = m.asprs_class;
        list.push_back(std::move(entry));
    }
    j["meshes"] = std::move(list);
    return j.dump(2) + "\n";
}

std::vector<std::string> ItemPlan::generateArgs() const {
    std::vector<std::string> args;
    for (const auto& [key, value] : values) {
        const VaryKey* k = findVaryKey(key);
        if (!k) continue;
        // Each of the key's options (resolution: --xres and --yres) takes the value.
        for (std::size_t at = 0; at < k->options.size();) {
            const std::size_t end = std::min(k->options.find(' ', at), k->options.size());
            args.insert(args.end(), {std::string(k->options.substr(at, end - at)),
                                     k->names ? std::string(k->names()[std::size_t(value)]) : exactNumber(value)});
            at = end + 1;
        }
    }
    if (centre_world)
        args.insert(args.end(), {"--centre", exactNumber(centre_world->x) + "," + exactNumber(centre_world->y) + "," +
                                                 exactNumber(centre_world->z)});
    return args;
}

struct Planner::State {
    Spec spec;
    std::optional<glm::dvec3> origin;
    std::vector<MeshEntry> entries;
    core::Scene base;
    std::unique_ptr<sim::RayCaster> ground;       // ground meshes only
    double ray_top_local = 0.0;                   // above every mesh, local frame
    std::vector<core::Bounds> boxes;              // world box per mesh (environment ones used)
    std::vector<std::size_t> environment;         // indices of environment meshes
    int target = -1;                              // index of the one target mesh, -1 if not one
    std::vector<std::vector<glm::dvec3>> models;  // per target_files entry, or the base's
    double clearance_m = 0.0;                     // base target's lowest point above the ground
};

Planner::Planner(const Spec& spec) : state_(std::make_unique<State>()) {
    State& s = *state_;
    s.spec = spec;
    const std::string prefix = "corpus: " + core::printable(spec.file.string()) + ": ";
    const std::string text =
        platform::readTextFile(spec.scene, io::kMaxSceneBytes, "corpus: scene " + core::printable(spec.scene.string()));
    s.base = io::loadSceneJson(text, spec.scene);  // validates the scene and every mesh
    // The entries as the scene parser read them: every field an item's scene copies.
    s.origin = s.base.written_origin;
    const fs::path dir = spec.scene.parent_path();
    for (const core::SceneEntry& m : s.base.entries) {
        MeshEntry e;
        e.written = m.file;
        e.file = fs::absolute(dir / e.written).lexically_normal();
        e.role = std::string(core::roleName(m.role));
        e.position = m.position;
        e.yaw_deg = m.yaw_deg;
        e.pitch_deg = m.pitch_deg;
        e.roll_deg = m.roll_deg;
        e.scale = m.scale;
        e.up = m.up_y ? "y" : "z";
        e.reflectance = m.reflectance;
        e.asprs_class = m.asprs_class;
        s.entries.push_back(std::move(e));
    }
    if (s.entries.size() != s.base.meshes.size())
        throw core::Error(prefix + "scene: " + std::to_string(s.entries.size()) + " entries but " +
                          std::to_string(s.base.meshes.size()) + " meshes loaded");
    int targets = 0;
    for (std::size_t k = 0; k < s.base.meshes.size(); ++k) {
        core::Bounds b;
        for (const glm::vec3& v : s.base.meshes[k].vertices) b.extend(s.base.origin + glm::dvec3(v));
        s.boxes.push_back(b);
        if (s.base.meshes[k].role == core::Role::Environment) s.environment.push_back(k);
        if (s.base.meshes[k].role == core::Role::Target) {
            ++targets;
            s.target = int(k);
        }
    }
    const bool moves = spec.varies("target_offset_m") || spec.varies("target_files");
    if ((moves || spec.varies("target_yaw_deg")) && targets != 1)
        throw core::Error(prefix + "vary: the target_* keys need a scene with exactly one target mesh; '" +
                          core::printable(spec.scene.string()) + "' has " + std::to_string(targets));
    if (targets != 1) s.target = -1;
    if (s.base.hasRole(core::Role::Ground)) {
        s.ground = std::make_unique<sim::RayCaster>(s.base, core::RoleMask::of({core::Role::Ground}));
        s.ray_top_local = s.base.bounds().hi.z + 10.0;
    } else if (moves || spec.varies("centre_offset_m")) {
        throw core::Error(prefix +
                          "vary: target_offset_m, target_files and centre_offset_m place things on the "
                          "ground; '" +
                          core::printable(spec.scene.string()) + "' has no ground mesh");
    }
    if (s.target >= 0) {
        const MeshEntry& t = s.entries[std::size_t(s.target)];
        const std::string base_where = "corpus: scene " + core::printable(spec.scene.string()) + ": meshes[" +
                                       std::to_string(s.target) + "] (the target)";
        if (spec.target_files.empty()) {
            s.models.push_back(loadModel(t.file, t.up, t.scale, base_where));
        } else {
            for (std::size_t i = 0; i < spec.target_files.size(); ++i) {
                const TargetModel& m = spec.target_files[i];
                s.models.push_back(
                    loadModel(m.file, m.up, m.scale, prefix + "vary.target_files[" + std::to_string(i) + "]"));
            }
        }
        // The base target's clearance: its lowest vertex above the ground under it.
        const std::vector<glm::dvec3> base_model =
            spec.target_files.empty() ? s.models.front() : loadModel(t.file, t.up, t.scale, base_where);
        double lo_z = 1e300;
        for (const glm::dvec3& v : base_model) lo_z = std::min(lo_z, v.z);
        const std::optional<double> g = groundZ(t.position.x, t.position.y);
        if (g && !base_model.empty()) s.clearance_m = t.position.z + lo_z - *g;
    }
}

Planner::~Planner() = default;

const Spec& Planner::spec() const { return state_->spec; }
const std::vector<core::Bounds>& Planner::environmentBoxes() const { return state_->boxes; }

std::string itemId(std::size_t index, std::size_t count) {
    const std::size_t digits = std::max<std::size_t>(4, std::to_string(count > 0 ? count - 1 : 0).size());
    const std::string id = std::to_string(index);
    return std::string(digits > id.size() ? digits - id.size() : 0, '0') + id;
}

std::string Planner::itemId(std::size_t index) const { return corpus::itemId(index, state_->spec.count); }

std::optional<double> Planner::groundZ(double x_world, double y_world) const {
    const State& s = *state_;
    if (!s.ground) return std::nullopt;
    sim::Ray ray;
    ray.origin = glm::vec3(glm::dvec3(x_world, y_world, 0.0) - glm::dvec3(s.base.origin.x, s.base.origin.y, 0.0));
    ray.origin.z = float(s.ray_top_local);
    ray.direction = {0.0f, 0.0f, -1.0f};
    ray.t_far = 1e30f;
    sim::Hit hit;
    s.ground->intersect(std::span<const sim::Ray>(&ray, 1), std::span<sim::Hit>(&hit, 1));
    if (!hit.hit()) return std::nullopt;
    return s.base.origin.z + double(ray.origin.z) - double(hit.t);
}

ItemPlan Planner::plan(std::size_t index) const {
    const State& s = *state_;
    const Spec& spec = s.spec;
    ItemPlan p;
    p.index = index;
    p.id = itemId(index);
    p.item_seed = itemSeed(spec.seed, index);
    p.origin = s.origin;
    const std::string where = "corpus: item " + p.id + ": ";

    // Plain values: one draw each from the key's stream.
    for (const auto& [key, n] : spec.numbers) {
        if (key == "target_offset_m" || key == "centre_offset_m") continue;  // drawn with their angle below
        SplitMix64 r = keyStream(p.item_seed, key);
        double v = n.min;
        if (n.kind == NumberVary::Kind::Choice)
            v = n.choices[std::size_t(r.below(n.choices.size()))];
        else if (n.kind == NumberVary::Kind::Uniform)
            v = n.integer ? n.min + double(r.below(std::uint64_t(n.max - n.min) + 1)) : r.uniform(n.min, n.max);
        p.values[key] = v;
        applyToOptions(p.options, key, v);
    }

    // Environment meshes kept: a partial Fisher-Yates shuffle of their indices.
    std::vector<std::size_t> kept = s.environment;
    p.environment_total = kept.size();
    if (const auto it = p.values.find("environment_keep_fraction"); it != p.values.end()) {
        const std::size_t k = std::size_t(std::llround(it->second * double(kept.size())));
        SplitMix64 r = keyStream(p.item_seed, "environment_keep");
        for (std::size_t i = 0; i < k; ++i) std::swap(kept[i], kept[i + std::size_t(r.below(kept.size() - i))]);
        kept.resize(k);
        std::sort(kept.begin(), kept.end());
    }
    p.environment_kept = kept.size();
    std::vector<bool> keep(s.entries.size(), true);
    for (std::size_t k : s.environment) keep[k] = false;
    for (std::size_t k : kept) keep[k] = true;

    // The target: model, yaw, place.
    std::optional<MeshEntry> target;
    if (s.target >= 0) {
        target = s.entries[std::size_t(s.target)];
        p.target_file = target->written;
        std::size_t model = 0;
        if (!spec.target_files.empty()) {
            model = std::size_t(keyStream(p.item_seed, "target_files").below(spec.target_files.size()));
            const TargetModel& m = spec.target_files[model];
            target->file = m.file;
            target->written = m.written;
            target->up = m.up;
            target->scale = m.scale;
            p.target_file = m.written;
        }
        if (const auto it = p.values.find("target_yaw_deg"); it != p.values.end()) target->yaw_deg = it->second;
        p.target_yaw_deg = target->yaw_deg;
        const double yaw = target->yaw_deg * std::numbers::pi / 180.0;
        const double c = std::cos(yaw), sn = std::sin(yaw);
        core::Bounds local;  // the model's box after yaw, relative to its position
        for (const glm::dvec3& m : s.models[model]) {
            const glm::dvec3 v = core::tilt(m, target->pitch_deg, target->roll_deg);
            local.extend(glm::dvec3(c * v.x - sn * v.y, sn * v.x + c * v.y, v.z));
        }
        const bool moves = spec.varies("target_offset_m") || spec.varies("target_files");
        if (moves) {
            const NumberVary* offset = nullptr;
            if (const auto it = spec.numbers.find("target_offset_m"); it != spec.numbers.end()) offset = &it->second;
            SplitMix64 r = keyStream(p.item_seed, "target_offset_m");
            const glm::dvec3 base = target->position;
            bool placed = false;
            for (int draw = 1; draw <= kMaxPlacementDraws && !placed; ++draw) {
                p.placement_draws = draw;
                double radius = 0.0;
                if (offset) {
                    const double lo = offset->lowest(), hi = offset->highest();
                    if (offset->kind == NumberVary::Kind::Choice)
                        radius = offset->choices[std::size_t(r.below(offset->choices.size()))];
                    else  // uniform over the annulus lo <= r <= hi
                        radius = std::sqrt(r.uniform(lo * lo, hi * hi));
                }
                const double angle = 2.0 * std::numbers::pi * r.unit();
                const double x = base.x + radius * std::cos(angle), y = base.y + radius * std::sin(angle);
                const std::optional<double> g = groundZ(x, y);
                if (!g) continue;  // off the ground: redraw
                const glm::dvec3 pos(x, y, *g + s.clearance_m - local.lo.z);
                core::Bounds box;
                box.extend(pos + local.lo);
                box.extend(pos + local.hi);
                bool clear = true;
                for (std::size_t k : kept)
                    clear = clear &&
                            !(overlaps(box, s.boxes[k]) &&
                              (!spec.place_by_triangles || trianglesOverlap(s.base.meshes[k], s.base.origin, box)));
                if (!clear) continue;
                target->position = pos;
                if (offset) p.values["target_offset_m"] = radius;
                placed = true;
            }
            if (!placed) {
                std::string range = "0";
                if (offset)
                    range =
                        "[" + core::shownNumber(offset->lowest()) + ", " + core::shownNumber(offset->highest()) + "]";
                throw core::Error(where + "the target cannot be placed: " + std::to_string(kMaxPlacementDraws) +
                                  " draws with target_offset_m " + range +
                                  " m all met another mesh's box or left the ground; allowed: a wider "
                                  "target_offset_m, a lower environment_keep_fraction, or more room around the target");
            }
        }
        p.target_position_world = target->position;
        p.target_box_world.extend(target->position + local.lo);
        p.target_box_world.extend(target->position + local.hi);
    }

    // The orbit centre C: moved away from the target when centre_offset_m varies.
    if (const auto it = spec.numbers.find("centre_offset_m"); it != spec.numbers.end()) {
        const NumberVary& n = it->second;
        glm::dvec3 c0 = s.base.origin + s.base.bounds().centre();
        if (!p.target_box_world.empty()) c0 = p.target_box_world.centre();
        SplitMix64 r = keyStream(p.item_seed, "centre_offset_m");
        for (int draw = 1; draw <= kMaxPlacementDraws && !p.centre_world; ++draw) {
            p.centre_draws = draw;
            const double radius = n.kind == NumberVary::Kind::Choice
                                      ? n.choices[std::size_t(r.below(n.choices.size()))]
                                      : std::sqrt(r.uniform(n.lowest() * n.lowest(), n.highest() * n.highest()));
            const double angle = 2.0 * std::numbers::pi * r.unit();
            const double x = c0.x + radius * std::cos(angle), y = c0.y + radius * std::sin(angle);
            const std::optional<double> g = groundZ(x, y);
            if (!g) continue;
            p.centre_world = glm::dvec3(x, y, *g);
            p.values["centre_offset_m"] = radius;
        }
        if (!p.centre_world)
            throw core::Error(where + "the orbit centre cannot be placed: " + std::to_string(kMaxPlacementDraws) +
                              " draws with centre_offset_m [" + core::shownNumber(n.lowest()) + ", " +
                              core::shownNumber(n.highest()) +
                              "] m all left the ground; allowed: a smaller "
                              "centre_offset_m");
        p.options.centre = p.centre_world;
    }

    for (std::size_t k = 0; k < s.entries.size(); ++k) {
        if (!keep[k]) continue;
        p.meshes.push_back(int(k) == s.target && target ? *target : s.entries[k]);
    }
    return p;
}

}  // namespace corpus
