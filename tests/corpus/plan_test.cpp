// tests/corpus/plan_test.cpp: items planned from (seed, index) alone; sampled values cover
// their ranges; the target stands on the ground and never meets another mesh's box; an
// item whose target cannot be placed is an error naming it.
#include <corpus/plan.hpp>

#include <core/error.hpp>
#include <io/scene_file.hpp>

#include <doctest/doctest.h>

#include "test_files.hpp"
#include <test_paths.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <thread>

using test_support::errorOf;

namespace {

const std::string kScene = std::string(test_support::corpusDataDir()) + "/scene.json";

corpus::Spec spec(const std::string& vary, std::size_t count = 300) {
    return corpus::parseSpec(R"({"scene": ")" + kScene + R"(", "count": )" + std::to_string(count) +
                                 R"(, "seed": 7, "vary": {)" + vary + "}}",
                             std::filesystem::path(test_support::corpusDataDir()) / "spec.json");
}

const std::string kVaried = R"("target_yaw_deg": {"min": 0, "max": 360}, "target_offset_m": {"min": 0, "max": 20},
    "environment_keep_fraction": {"min": 0.5, "max": 1.0}, "altitude_m": {"min": 200, "max": 400},
    "alpha_deg": {"min": 30, "max": 60}, "fov_deg": {"min": 4, "max": 8}, "resolution": [16, 24, 32],
    "views": {"min": 3, "max": 6}, "centre_offset_m": {"min": 0, "max": 15})";

bool samePlan(const corpus::ItemPlan& a, const corpus::ItemPlan& b) {
    return a.values == b.values && a.target_position_world == b.target_position_world &&
           a.target_yaw_deg == b.target_yaw_deg && a.centre_world == b.centre_world &&
           a.sceneText({}) == b.sceneText({}) && a.generateArgs() == b.generateArgs();
}

bool overlaps(const core::Bounds& a, const core::Bounds& b) {
    for (int k = 0; k < 3; ++k)
        if (a.hi[k] <= b.lo[k] || b.hi[k] <= a.lo[k]) return false;
    return true;
}

}  // namespace

TEST_CASE("plan: sampled values stay in their ranges and cover them") {
    const corpus::Spec s = spec(kVaried);
    const corpus::Planner planner(s);
    std::map<std::string, std::set<int>> bins;  // 10 bins per uniform key
    std::set<double> resolutions, views;
    for (std::size_t i = 0; i < s.count; ++i) {
        const corpus::ItemPlan p = planner.plan(i);
        for (const auto& [key, n] : s.numbers) {
            REQUIRE(p.values.count(key));
            const double v = p.values.at(key);
            CHECK(v >= n.lowest());
            CHECK(v <= n.highest());
            if (n.kind == corpus::NumberVary::Kind::Uniform && !n.integer)
                bins[key].insert(std::min(9, int((v - n.min) / (n.max - n.min) * 10)));
        }
        resolutions.insert(p.values.at("resolution"));
        views.insert(p.values.at("views"));
        CHECK(p.options.orbit.xres == int(p.values.at("resolution")));
        CHECK(p.options.orbit.altitude_m == p.values.at("altitude_m"));
        CHECK(p.environment_kept >= 2);  // half of 4 environment meshes at least
        CHECK(p.environment_kept <= 4);
    }
    for (const auto& [key, b] : bins) {
        INFO(key);
        // target_offset_m is uniform over the disc (the area), so its small radii are rarer
        // but still drawn in 300 items.
        CHECK(b.size() == 10);
    }
    CHECK(resolutions == std::set<double>{16, 24, 32});
    CHECK(views == std::set<double>{3, 4, 5, 6});
}

TEST_CASE("plan: item i depends on (seed, i) alone, not on order, other items or threads") {
    const corpus::Spec s = spec(kVaried, 40);
    const corpus::Planner a(s);
    std::vector<corpus::ItemPlan> forward;
    for (std::size_t i = 0; i < s.count; ++i) forward.push_back(a.plan(i));
    const corpus::Planner b(s);
    std::vector<corpus::ItemPlan> threaded(s.count);
    std::vector<std::thread> pool;
    for (int t = 0; t < 4; ++t)
        pool.emplace_back([&, t] {
            for (std::size_t i = s.count; i-- > 0;)
                if (int(i % 4) == t) threaded[i] = b.plan(i);
        });
    for (std::thread& t : pool) t.join();
    for (std::size_t i = 0; i < s.count; ++i) CHECK(samePlan(forward[i], threaded[i]));
    // Another seed gives other items.
    corpus::Spec other = s;
    other.seed = 8;
    const corpus::Planner c(other);
    CHECK_FALSE(samePlan(c.plan(3), forward[3]));
    // Adding a varied key leaves the other keys' values alone (one stream per key).
    const corpus::Planner d(spec(kVaried + R"(, "band_m": {"min": 2, "max": 4})", 40));
    CHECK(d.plan(5).values.at("altitude_m") == forward[5].values.at("altitude_m"));
}

TEST_CASE("plan: the target stands on the ground and never meets another mesh's box") {
    const corpus::Spec s =
        spec(R"("target_yaw_deg": {"min": 0, "max": 360}, "target_offset_m": {"min": 0, "max": 30})", 25);
    const corpus::Planner planner(s);
    const auto& boxes = planner.environmentBoxes();
    int moved_far = 0;
    for (std::size_t i = 0; i < s.count; ++i) {
        const corpus::ItemPlan p = planner.plan(i);
        // The concrete scene as the generator loads it.
        const core::Scene scene = io::loadSceneJson(p.sceneText({}), "item.json");
        core::Bounds target;
        for (const core::Mesh& m : scene.meshes)
            if (m.role == core::Role::Target)
                for (const glm::vec3& v : m.vertices) target.extend(scene.origin + glm::dvec3(v));
        for (const core::Mesh& m : scene.meshes) {
            if (m.role != core::Role::Environment) continue;
            core::Bounds b;
            for (const glm::vec3& v : m.vertices) b.extend(scene.origin + glm::dvec3(v));
            INFO("item " << p.id << " mesh " << m.name);
            CHECK_FALSE(overlaps(target, b));
        }
        CHECK(std::abs(target.lo.z - p.target_box_world.lo.z) < 1e-3);
        // On the (flat, near z = 0) ground, lowest point a few cm from it as in the base scene.
        const auto g = planner.groundZ(p.target_position_world.x, p.target_position_world.y);
        REQUIRE(g);
        CHECK(std::abs(target.lo.z - *g) < 0.5);
        if (glm::length(glm::dvec2(p.target_position_world) - glm::dvec2(0.0)) > 15.0) ++moved_far;
    }
    CHECK(boxes.size() == 6);
    CHECK(moved_far > 5);
}

TEST_CASE("plan: an item whose target cannot be placed is an error naming it") {
    // The ground is 300 m across: 400-500 m away every draw leaves it.
    const corpus::Planner planner(spec(R"("target_offset_m": {"min": 400, "max": 500})", 3));
    const std::string e = errorOf([&] { planner.plan(2); });
    CHECK(e.rfind("corpus: item 0002: the target cannot be placed", 0) == 0);
    CHECK(e.find("target_offset_m [400, 500]") != std::string::npos);
    const std::string c =
        errorOf([&] { corpus::Planner(spec(R"("centre_offset_m": {"min": 400, "max": 500})", 3)).plan(0); });
    CHECK(c.rfind("corpus: item 0000: the orbit centre cannot be placed", 0) == 0);
}

TEST_CASE("plan: the scene file names meshes relative to the item folder and replays the options") {
    const corpus::Spec s = spec(kVaried, 5);
    const corpus::Planner planner(s);
    const corpus::ItemPlan p = planner.plan(1);
    const std::filesystem::path folder = std::filesystem::path(test_support::corpusDataDir()) / "out" / "items" / p.id;
    const std::string text = p.sceneText(folder);
    CHECK(text.find("\"../../../../../../assets/common/tank.obj\"") != std::string::npos);
    CHECK(text.find("--altitude-m") != std::string::npos);
    const auto args = p.generateArgs();
    const auto at = std::find(args.begin(), args.end(), "--centre");
    REQUIRE(at != args.end());
    CHECK(std::count(at[1].begin(), at[1].end(), ',') == 2);
}

TEST_CASE("plan: an item's sensor preset is replayed by its name") {
    const corpus::Planner planner(spec(R"("sensor_preset": "riegl-vux1uav")", 2));
    const auto args = planner.plan(0).generateArgs();
    const auto at = std::find(args.begin(), args.end(), "--sensor");
    REQUIRE(at != args.end());
    REQUIRE(at + 1 != args.end());
    CHECK(at[1] == "riegl-vux1uav");
}

TEST_CASE("plan: target_files draws every model, each placed clear of the buildings") {
    const std::string assets = test_support::assetsDir();
    const corpus::Spec s =
        spec(R"("target_files": [")" + assets + R"(/common/tank.obj", {"file": ")" + assets +
                 R"(/common/house_small.obj", "scale": 0.5}], "target_offset_m": {"min": 0, "max": 25})",
             60);
    const corpus::Planner planner(s);
    const auto& boxes = planner.environmentBoxes();  // scene order: ground, target, 4 environment meshes
    REQUIRE(boxes.size() == 6);
    std::set<std::string> drawn;
    int redrawn = 0;  // items whose first draws met a building: the check did bite
    for (std::size_t i = 0; i < s.count; ++i) {
        const corpus::ItemPlan p = planner.plan(i);
        drawn.insert(p.target_file);
        redrawn += p.placement_draws > 1;
        for (std::size_t k = 2; k < boxes.size(); ++k) CHECK_FALSE(overlaps(p.target_box_world, boxes[k]));
        const auto target = std::find_if(p.meshes.begin(), p.meshes.end(),
                                         [](const corpus::MeshEntry& m) { return m.role == "target"; });
        REQUIRE(target != p.meshes.end());
        CHECK(target->written == p.target_file);
        CHECK(target->scale == (p.target_file.ends_with("house_small.obj") ? 0.5 : 1.0));
    }
    CHECK(drawn.size() == 2);
    CHECK(redrawn > 0);
}

TEST_CASE("plan: a tilted mesh keeps its tilt, and the target's box follows it") {
    // The forest's tank rests tilted across its slope (roll_deg); an item that does not
    // move it places it exactly as the scene does.
    const std::string forest = std::string(test_support::assetsDir()) + "/forest/scene.json";
    const corpus::Spec s = corpus::parseSpec(R"({"scene": ")" + forest + R"(", "count": 1, "seed": 3, "vary": {}})",
                                             std::filesystem::path(test_support::corpusDataDir()) / "spec.json");
    const corpus::ItemPlan p = corpus::Planner(s).plan(0);
    const std::string text = p.sceneText({});
    CHECK(text.find("\"roll_deg\"") != std::string::npos);
    const core::Scene item = io::loadSceneJson(text, forest);
    const core::Scene base = io::loadScene(forest);
    const core::Bounds a = item.bounds(core::RoleMask::of({core::Role::Target}));
    const core::Bounds b = base.bounds(core::RoleMask::of({core::Role::Target}));
    CHECK(a.lo == b.lo);
    CHECK(a.hi == b.hi);
    // The planned box (world) is the tilted tank's: its downhill track reaches about
    // 0.45 m lower than a level tank's would.
    const glm::dvec3 lo = p.target_box_world.lo - base.origin, hi = p.target_box_world.hi - base.origin;
    CHECK(lo.z == doctest::Approx(b.lo.z).epsilon(1e-4));
    CHECK(hi.z == doctest::Approx(b.hi.z).epsilon(1e-4));
}

namespace {

// An OBJ cube of edge `e` with its bottom centre at (x, y, 0); vertex numbers from `first`.
std::string cube(double x, double y, double e, int first) {
    std::string s;
    for (int k = 0; k < 8; ++k)
        s += "v " + std::to_string(x + ((k & 1) ? e / 2 : -e / 2)) + " " +
             std::to_string(y + ((k & 2) ? e / 2 : -e / 2)) + " " + std::to_string((k & 4) ? e : 0.0) + "\n";
    const int f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                          {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    for (const auto& t : f)
        s += "f " + std::to_string(first + t[0]) + " " + std::to_string(first + t[1]) + " " +
             std::to_string(first + t[2]) + "\n";
    return s;
}

}  // namespace

TEST_CASE("plan: placement by triangles lets a target move inside one environment mesh spread over the scene") {
    // One environment mesh of two cubes 40 m apart (as `scene from-cloud` makes one mesh of
    // a survey's boxes): its box covers the whole ground, so by boxes no place is free.
    const test_support::TempDir dir("plan_triangles");
    dir.write("ground.obj", "v -50 -50 0\nv 50 -50 0\nv 50 50 0\nv -50 50 0\nf 1 2 3\nf 1 3 4\n");
    dir.write("clutter.obj", cube(-20, -20, 6, 1) + cube(20, 20, 6, 9));
    dir.write("target.obj", cube(0, 0, 2, 1));
    dir.write("scene.json", R"({"meshes": [{"file": "ground.obj", "role": "ground"},
        {"file": "clutter.obj", "role": "environment"}, {"file": "target.obj", "role": "target"}]})");
    auto make = [&](const std::string& placement) {
        return corpus::parseSpec(R"({"scene": "scene.json", "count": 20, "seed": 3, )" + placement +
                                     R"("vary": {"target_offset_m": {"min": 0, "max": 20}}})",
                                 dir.path / "spec.json");
    };
    const corpus::Planner by_boxes(make(""));
    CHECK(errorOf([&] { by_boxes.plan(0); }).find("the target cannot be placed") != std::string::npos);
    const corpus::Spec s = make(R"("placement": "triangles", )");
    CHECK(s.place_by_triangles);
    const corpus::Planner by_triangles(s);
    core::Bounds a, b;
    a.extend({-23, -23, 0}), a.extend({-17, -17, 6});
    b.extend({17, 17, 0}), b.extend({23, 23, 6});
    std::size_t moved = 0;
    for (std::size_t i = 0; i < s.count; ++i) {
        const corpus::ItemPlan p = by_triangles.plan(i);
        CHECK_FALSE(overlaps(p.target_box_world, a));
        CHECK_FALSE(overlaps(p.target_box_world, b));
        CHECK(p.target_box_world.lo.z == doctest::Approx(0.0));
        moved += p.target_position_world.x != 0.0;
    }
    CHECK(moved == s.count);
    CHECK(errorOf([&] { make(R"("placement": "exact", )"); }).find("allowed \"boxes\" or \"triangles\"") !=
          std::string::npos);
}
