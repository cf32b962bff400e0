// Scene loading: transforms, frames, roles, the bundled scenes, and one test per kind
// of bad scene file (each must give its one-line error naming the file and the reason).
#include <test_files.hpp>
#include <test_paths.hpp>
#include <core/error.hpp>
#include <io/scene_file.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <string>

#include <unistd.h>

namespace fs = std::filesystem;
using core::Role;
using core::RoleMask;

namespace {

const fs::path kScenes = fs::path(test_support::dataDir()) / "scenes";
const fs::path kBad = kScenes / "bad";
const fs::path kAssets = fs::path(test_support::assetsDir());

// The message of the Error that loading `file` throws; fails the test if none is thrown.
std::string loadError(const fs::path& file, io::SceneLoadOptions options = {}) {
    try {
        io::loadScene(file, options);
    } catch (const core::Error& e) {
        return e.what();
    }
    FAIL("no error for " << file.string());
    return {};
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A fresh directory under /tmp for scenes written by a test; removed at scope exit.
using test_support::TempDir;
core::Bounds meshBounds(const core::Mesh& m) {
    core::Bounds b;
    for (const glm::vec3& v : m.vertices) b.extend(glm::dvec3(v));
    return b;
}

const std::string kBox = (kScenes / "basic" / "box.obj").string();

}  // namespace

TEST_CASE("scene: role names parse and print") {
    CHECK(core::roleName(Role::Ground) == "ground");
    CHECK(core::roleName(Role::Environment) == "environment");
    CHECK(core::roleName(Role::Target) == "target");
    CHECK(core::parseRole("target", "ctx") == Role::Target);
    try {
        core::parseRole("tank", "--role");
        FAIL("no error");
    } catch (const core::Error& e) {
        CHECK(std::string(e.what()) == "--role: role 'tank' is not one of ground, environment, target");
    }
}

TEST_CASE("scene: RoleMask parses comma-separated lists") {
    const RoleMask m = RoleMask::parse("target, environment", "--roles");
    CHECK(m.has(Role::Target));
    CHECK(m.has(Role::Environment));
    CHECK_FALSE(m.has(Role::Ground));
    CHECK(RoleMask::parse("ground", "--roles").bits == 0b001);
    CHECK(RoleMask::of({Role::Target, Role::Ground}).bits == 0b101);
    CHECK(RoleMask::all().bits == 0b111);
    CHECK_THROWS_WITH_AS(RoleMask::parse("", "--roles"), doctest::Contains("--roles: empty role"), core::Error);
    CHECK_THROWS_WITH_AS(RoleMask::parse("target,,ground", "--roles"), doctest::Contains("--roles: empty role"),
                         core::Error);
    CHECK_THROWS_WITH_AS(RoleMask::parse("target,trees", "--roles"),
                         "--roles: role 'trees' is not one of ground, environment, target", core::Error);
}

TEST_CASE("scene: the basic scene loads with position, yaw, scale and up applied") {
    const core::Scene s = io::loadScene(kScenes / "basic" / "scene.json");
    REQUIRE(s.meshes.size() == 3);
    CHECK(s.source == kScenes / "basic" / "scene.json");
    // No origin key: the first mesh's position (0, 0, 0).
    CHECK(s.origin == glm::dvec3(0.0));
    CHECK(s.meshes[0].name == "ground.obj");
    CHECK(s.meshes[0].role == Role::Ground);
    CHECK(s.meshes[0].triangles.size() == 2);  // the zero-area third face is dropped
    CHECK(s.skipped_triangles == 1);
    CHECK(s.meshes[1].triangles.size() == 12);
    CHECK(s.triangleCount() == 26);
    CHECK(s.hasRole(Role::Environment));

    // Target: the unit cube scaled 2, yawed +90 deg about z (x -> y), at (2, 3, 0):
    // x in [0, 2], y in [3, 5], z in [0, 2].
    const core::Bounds t = s.bounds(RoleMask::of({Role::Target}));
    CHECK(t.lo.x == doctest::Approx(0.0).epsilon(1e-6));
    CHECK(t.hi.x == doctest::Approx(2.0));
    CHECK(t.lo.y == doctest::Approx(3.0));
    CHECK(t.hi.y == doctest::Approx(5.0));
    CHECK(t.lo.z == doctest::Approx(0.0));
    CHECK(t.hi.z == doctest::Approx(2.0));
    // The +90 deg yaw maps the cube's corner (1, 0, 0) to (0, 1, 0) * 2 + (2, 3, 0).
    bool found = false;
    for (const glm::vec3& v : s.meshes[1].vertices)
        found = found || (std::abs(v.x - 2.0f) < 1e-5f && std::abs(v.y - 5.0f) < 1e-5f && v.z == 0.0f);
    CHECK(found);

    // up: y maps file (x, y, z) to (x, -z, y): the cube at (-5, 0, 0) spans
    // x in [-5, -4], y in [-1, 0], z in [0, 1].
    const core::Bounds e = meshBounds(s.meshes[2]);
    CHECK(e.lo == glm::dvec3(-5.0, -1.0, 0.0));
    CHECK(e.hi == glm::dvec3(-4.0, 0.0, 1.0));

    // Ground: 20 m x 20 m at z = 0.
    const core::Bounds g = s.bounds(RoleMask::of({Role::Ground}));
    CHECK(g.lo == glm::dvec3(-10.0, -10.0, 0.0));
    CHECK(g.hi == glm::dvec3(10.0, 10.0, 0.0));
    CHECK(s.bounds().hi.z == doctest::Approx(2.0));
}

TEST_CASE("scene: --roles leaves other meshes out but keeps the origin") {
    io::SceneLoadOptions o;
    o.roles = RoleMask::of({Role::Target});
    const core::Scene s = io::loadScene(kScenes / "basic" / "scene.json", o);
    REQUIRE(s.meshes.size() == 1);
    CHECK(s.meshes[0].role == Role::Target);
    CHECK(s.origin == glm::dvec3(0.0));
    CHECK_FALSE(s.hasRole(Role::Ground));
    CHECK(s.bounds(RoleMask::of({Role::Ground})).empty());
}

TEST_CASE("scene: georeferenced scenes keep centimetres in the local frame") {
    TempDir dir("geo");
    SUBCASE("explicit origin") {
        // Mesh at origin + (10, 20, -100): local vertices are exactly the cube moved there.
        const fs::path f = dir.write("scene.json",
                                     "{ \"origin\": [1000000.5, 20000000.25, 100],\n"
                                     "  \"meshes\": [ { \"file\": \"" +
                                         kBox +
                                         "\", \"role\": \"target\",\n"
                                         "                  \"position\": [1000010.5, 20000020.25, 0] } ] }");
        const core::Scene s = io::loadScene(f);
        CHECK(s.origin == glm::dvec3(1000000.5, 20000000.25, 100.0));
        const core::Bounds b = meshBounds(s.meshes[0]);
        CHECK(b.lo == glm::dvec3(10.0, 20.0, -100.0));
        CHECK(b.hi == glm::dvec3(11.0, 21.0, -99.0));
    }
    SUBCASE("default origin: the first mesh's position") {
        const fs::path f =
            dir.write("scene.json", "{ \"meshes\": [ { \"file\": \"" + kBox +
                                        "\", \"role\": \"ground\",\n"
                                        "                  \"position\": [5123456.78, 3123456.91, 50.5] },\n"
                                        "                { \"file\": \"" +
                                        kBox +
                                        "\", \"role\": \"target\",\n"
                                        "                  \"position\": [5123456.79, 3123456.91, 50.5] } ] }");
        const core::Scene s = io::loadScene(f);
        CHECK(s.origin == glm::dvec3(5123456.78, 3123456.91, 50.5));
        CHECK(meshBounds(s.meshes[0]).lo == glm::dvec3(0.0));
        CHECK(meshBounds(s.meshes[0]).hi == glm::dvec3(1.0));
        // 1 cm east of the first: still resolved to well under a millimetre in float.
        CHECK(meshBounds(s.meshes[1]).lo.x == doctest::Approx(0.01).epsilon(1e-4));
    }
}

TEST_CASE("scene: require_target can be turned off") {
    io::SceneLoadOptions o;
    o.require_target = false;
    const core::Scene s = io::loadScene(kBad / "no_target.json", o);
    CHECK(s.meshes.size() == 2);
    CHECK_FALSE(s.hasRole(Role::Target));
}

TEST_CASE("scene: bad scene files give one clear line naming the file and the reason") {
    const std::string b = "scene: " + kBad.string() + "/";
    SUBCASE("a folder that holds a scene file (as `scene from-cloud` writes): the line names that file") {
        TempDir dir("scene_folder");
        std::ofstream(dir.path / "scene.json") << "{}";
        CHECK(loadError(dir.path) == "scene: " + dir.path.string() +
                                         ": is a folder; allowed a scene file (this folder's is " +
                                         (dir.path / "scene.json").string() + ")");
    }
    SUBCASE("missing scene file") {
        CHECK(loadError(kBad / "nothing_here.json") == b + "nothing_here.json: the scene file does not exist");
    }
    SUBCASE("JSON syntax error names the line") {
        const std::string m = loadError(kBad / "syntax.json");
        CHECK(contains(m, b + "syntax.json: JSON syntax error"));
        CHECK(contains(m, "line 4"));
    }
    SUBCASE("top level is not an object") {
        CHECK(loadError(kBad / "not_object.json") ==
              b + "not_object.json: the top level must be a JSON object with 'meshes', not an array");
    }
    SUBCASE("unknown key in a mesh entry") {
        CHECK(loadError(kBad / "unknown_key.json") ==
              b + "unknown_key.json: meshes[0] ('../basic/box.obj'): unknown key 'rol'; allowed "
                  "keys: file, role, position, yaw_deg, pitch_deg, roll_deg, scale, up, reflectance, class, comment");
    }
    SUBCASE("unknown top-level key") {
        CHECK(loadError(kBad / "unknown_top_key.json") ==
              b + "unknown_top_key.json: unknown key 'orgin'; allowed keys: origin, meshes, comment");
    }
    SUBCASE("wrong types") {
        CHECK(loadError(kBad / "wrong_type_scale.json") ==
              b + "wrong_type_scale.json: meshes[0] ('../basic/box.obj'): 'scale' must be a "
                  "finite number > 0, not a string");
        CHECK(contains(loadError(kBad / "wrong_type_position.json"),
                       "meshes[0] ('../basic/box.obj'): 'position' must be an array of 3 finite "
                       "numbers"));
        CHECK(loadError(kBad / "wrong_type_meshes.json") ==
              b + "wrong_type_meshes.json: 'meshes' must be a non-empty array of mesh entries");
    }
    SUBCASE("missing file or role") {
        CHECK(loadError(kBad / "missing_file_key.json") ==
              b + "missing_file_key.json: meshes[0]: 'file' is missing; it names a mesh file "
                  "relative to the scene file");
        CHECK(loadError(kBad / "missing_role.json") ==
              b + "missing_role.json: meshes[0] ('../basic/box.obj'): 'role' is missing; allowed: "
                  "ground, environment, target");
    }
    SUBCASE("missing mesh file") {
        const std::string m = loadError(kBad / "missing_mesh.json");
        CHECK(contains(m, b + "missing_mesh.json: meshes[1] ('no_such_mesh.obj'): mesh file '"));
        CHECK(contains(m, "no_such_mesh.obj' does not exist"));
    }
    SUBCASE("unreadable mesh: a directory") {
        CHECK(contains(loadError(kBad / "mesh_is_directory.json"), "is a directory; allowed: a regular file"));
    }
    SUBCASE("unreadable mesh: no read permission") {
        if (::geteuid() == 0) {
            MESSAGE("running as root: permissions do not stop reads, case not testable here");
        } else {
            TempDir dir("perm");
            fs::copy_file(kBox, dir.path / "box.obj");
            fs::permissions(dir.path / "box.obj", fs::perms::none);
            const fs::path f = dir.write("scene.json", "{\"meshes\": [{\"file\": \"box.obj\", \"role\": \"target\"}]}");
            CHECK(contains(loadError(f), "box.obj' cannot be read"));
        }
    }
    SUBCASE("Assimp cannot import the mesh") {
        const std::string m = loadError(kBad / "assimp_fails.json");
        CHECK(contains(m, b + "assimp_fails.json: meshes[0] ('not_a_mesh.xyz123'): Assimp cannot "
                              "import mesh file"));
        CHECK(contains(m, "allowed: a triangle mesh in a format Assimp reads"));
        CHECK(contains(loadError(kBad / "empty_mesh.json"), "meshes[0] ('empty.obj'): "));
    }
    SUBCASE("NaN vertex in the mesh file") {
        // An ASCII PLY whose vertex 1 is 'nan': Assimp keeps it, our check rejects it.
        CHECK(loadError(kBad / "nan_vertex.json") ==
              b + "nan_vertex.json: meshes[1] ('nan_vertex.ply'): mesh file '" + kBad.string() +
                  "/nan_vertex.ply': vertex 1 is not finite (nan, 1, 0); allowed: finite coordinates");
    }
    SUBCASE("unknown role") {
        CHECK(loadError(kBad / "unknown_role.json") ==
              b + "unknown_role.json: meshes[2] ('../basic/box.obj'): role 'buildng' is not one "
                  "of ground, environment, target");
    }
    SUBCASE("no target") {
        CHECK(loadError(kBad / "no_target.json") ==
              b + "no_target.json: no mesh has role 'target'; a scene needs at least one target mesh");
    }
    SUBCASE("no target in a folder scene from-cloud wrote: the line says how to give one") {
        TempDir dir("scene_no_vehicle");
        fs::copy_file(kScenes / "basic" / "ground.obj", dir.path / "ground.obj");
        std::ofstream(dir.path / "scene.json") << R"({"meshes": [{"file": "ground.obj", "role": "ground"}]})";
        std::ofstream(dir.path / "from_cloud.json") << "{}";
        CHECK(loadError(dir.path / "scene.json") ==
              "scene: " + (dir.path / "scene.json").string() +
                  ": no mesh has role 'target'; a scene needs at least one target mesh (scene from-cloud made this "
                  "one without --vehicle: give it a vehicle mesh)");
    }
    SUBCASE("non-finite position and yaw") {
        CHECK(loadError(kBad / "nonfinite_position.json") ==
              b + "nonfinite_position.json: number overflow parsing '1e999': the number is not "
                  "finite; allowed: finite numbers");
        CHECK(contains(loadError(kBad / "nonfinite_yaw.json"), "'-1e400': the number is not finite"));
    }
    SUBCASE("a transform that overflows float") {
        CHECK(contains(loadError(kBad / "overflow_transform.json"),
                       "meshes[0] ('../basic/box.obj'): vertex 1 lies 1e+300 m from the origin after "
                       "the position/yaw/tilt/scale transform; allowed: within 10000000 m of the scene's origin"));
    }
    SUBCASE("scale <= 0") {
        CHECK(loadError(kBad / "zero_scale.json") ==
              b + "zero_scale.json: meshes[0] ('../basic/box.obj'): 'scale' is 0; allowed: a "
                  "finite number > 0");
        CHECK(contains(loadError(kBad / "negative_scale.json"), "'scale' is -2; allowed"));
    }
    SUBCASE("up is not y or z") {
        CHECK(loadError(kBad / "bad_up.json") ==
              b + "bad_up.json: meshes[0] ('../basic/box.obj'): 'up' is 'x'; allowed: y, z");
    }
}

TEST_CASE("scene: a mesh made only of zero-area triangles is an error") {
    TempDir dir("degenerate");
    dir.write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    const fs::path f = dir.write("scene.json", "{\"meshes\": [{\"file\": \"flat.obj\", \"role\": \"target\"}]}");
    CHECK(contains(loadError(f), "meshes[0] ('flat.obj'): all 1 triangles have zero area"));
}

TEST_CASE("scene: errors in a later entry are found before any mesh is imported") {
    // The unknown role sits in entry 2; entry 0 names a missing file. Entries are checked
    // first, so the JSON mistake is reported, not the (later) missing file.
    TempDir dir("order");
    const fs::path f = dir.write("scene.json",
                                 "{\"meshes\": [{\"file\": \"missing.obj\", \"role\": \"target\"},"
                                 " {\"file\": \"missing.obj\", \"role\": \"tree\"}]}");
    CHECK(contains(loadError(f), "meshes[1] ('missing.obj'): role 'tree' is not one of"));
}

TEST_CASE("scene: skip_nonfinite drops the triangles of NaN vertices and counts them") {
    TempDir dir("skipnan");
    // Two triangles sharing an edge; vertex 3 (only in the second) is NaN.
    dir.write("some.ply",
              "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
              "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0\nnan 1 0\n3 0 1 2\n3 1 3 2\n");
    dir.write("some.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 inf 0\nf 1 2 3\nf 2 4 3\n");
    for (const std::string mesh : {"some.ply", "some.obj"}) {
        CAPTURE(mesh);
        const fs::path f = dir.write("scene.json", std::string("{\"meshes\": [{\"file\": \"") + mesh +
                                                       "\", \"role\": \"target\"}, "
                                                       "{\"file\": \"" +
                                                       mesh + "\", \"role\": \"ground\", \"position\": [5, 0, 0]}]}");
        // The vertex index is Assimp's: OBJ corners get their own vertices.
        CHECK(contains(loadError(f), mesh == "some.ply" ? "vertex 3 is not finite (nan, 1, 0)"
                                                        : "vertex 4 is not finite (1, inf, 0)"));
        io::SceneLoadOptions o;
        o.skip_nonfinite = true;
        const core::Scene s = io::loadScene(f, o);
        REQUIRE(s.meshes.size() == 2);
        CHECK(s.skipped_nonfinite_triangles == 2);  // one per entry using the file
        CHECK(s.skipped_triangles == 0);
        CHECK(s.meshes[0].triangles.size() == 1);
        const core::Bounds b = s.bounds();
        CHECK(b.lo == glm::dvec3(0.0));
        CHECK(b.hi == glm::dvec3(6.0, 1.0, 0.0));
    }
    // A mesh with nothing finite left is still an error.
    io::SceneLoadOptions o;
    o.skip_nonfinite = true;
    CHECK(contains(loadError(kBad / "nan_vertex.json", o), "contains no triangles with finite vertices"));
}

TEST_CASE("scene: --roles that leave no mesh are an error") {
    io::SceneLoadOptions o;
    o.require_target = false;
    o.roles = RoleMask::of({Role::Target});
    CHECK(loadError(kBad / "no_target.json", o) ==
          "scene: " + (kBad / "no_target.json").string() +
              ": no mesh has one of the selected roles; the file's roles are ground, environment");
}

TEST_CASE("scene: loadSceneJson reads text in memory relative to the named file") {
    const core::Scene s =
        io::loadSceneJson(R"({"meshes": [{"file": "box.obj", "role": "target", "position": [1, 1, 1]}]})",
                          kScenes / "basic" / "virtual.json");
    REQUIRE(s.meshes.size() == 1);
    CHECK(s.source == kScenes / "basic" / "virtual.json");
    CHECK(meshBounds(s.meshes[0]).hi == glm::dvec3(1.0));
    CHECK_THROWS_WITH_AS(io::loadSceneJson("{", "mem.json"), doctest::Contains("scene: mem.json: JSON syntax error"),
                         core::Error);
}

TEST_CASE("scene: roll and pitch tilt a mesh about its own axes before the yaw") {
    const fs::path at = kScenes / "basic" / "virtual.json";
    const auto cube = [&](const std::string& keys) {
        const core::Scene s = io::loadSceneJson(
            R"({"meshes": [{"file": "box.obj", "role": "target", "position": [10, 0, 0])" + keys + "}]}", at);
        REQUIRE(s.meshes.size() == 1);
        return s.meshes[0];
    };
    // The unit cube [0, 1]^3 (the origin is the first position, so local = file + shift 0).
    const auto has = [](const core::Mesh& m, glm::dvec3 p) {
        for (const glm::vec3& v : m.vertices)
            if (glm::length(glm::dvec3(v) - p) < 1e-5) return true;
        return false;
    };
    // Roll +90: +y up, so the corner (0, 1, 0) goes to (0, 0, 1) and (0, 0, 1) to (0, -1, 0).
    const core::Mesh rolled = cube(R"(, "roll_deg": 90)");
    CHECK(has(rolled, {0, 0, 1}));
    CHECK(has(rolled, {0, -1, 0}));
    CHECK(meshBounds(rolled).lo.y == doctest::Approx(-1.0));
    // Pitch +90: the nose (+x) down, so (1, 0, 0) goes to (0, 0, -1).
    const core::Mesh pitched = cube(R"(, "pitch_deg": 90)");
    CHECK(has(pitched, {0, 0, -1}));
    CHECK(has(pitched, {1, 0, 0}));  // (0, 0, 1) comes forward
    // Roll first, then pitch, then yaw: (0, 1, 0) rolls up to (0, 0, 1), pitches forward
    // to (1, 0, 0) and yaws to (0, 1, 0).
    const core::Mesh all = cube(R"(, "roll_deg": 90, "pitch_deg": 90, "yaw_deg": 90)");
    CHECK(has(all, {0, 1, 0}));
    // A tilt of zero places the vertices exactly as no tilt does.
    const core::Mesh plain = cube(R"(, "yaw_deg": 33)");
    const core::Mesh zero = cube(R"(, "yaw_deg": 33, "roll_deg": 0, "pitch_deg": 0)");
    CHECK(plain.vertices == zero.vertices);
    const std::string expected =
        "scene: " + at.string() + ": meshes[0] ('box.obj'): 'roll_deg' is 91; allowed: a number in [-90, 90] (degrees)";
    CHECK_THROWS_WITH_AS(cube(R"(, "roll_deg": 91)"), expected.c_str(), core::Error);
    CHECK_THROWS_WITH_AS(cube(R"(, "pitch_deg": "up")"),
                         doctest::Contains("'pitch_deg' must be a number in [-90, 90] (degrees), not a string"),
                         core::Error);
}

TEST_CASE("scene: the forest's tank rests on its slope") {
    // Tilted to the ground under it: no track corner floats or is buried by more than a
    // few centimetres (a level tank there floated 0.4 m on one side, buried on the other).
    const core::Scene s = io::loadScene(kAssets / "forest" / "scene.json");
    const core::Mesh* tank = nullptr;
    const core::Mesh* ground = nullptr;
    for (const core::Mesh& m : s.meshes) {
        if (m.role == Role::Target) tank = &m;
        if (m.role == Role::Ground) ground = &m;
    }
    REQUIRE(tank != nullptr);
    REQUIRE(ground != nullptr);
    // The ground's height under (x, y): the triangle of the ground mesh that holds it.
    const auto groundAt = [&](double x, double y) {
        for (const glm::uvec3& t : ground->triangles) {
            const glm::dvec3 a(ground->vertices[t.x]), b(ground->vertices[t.y]), c(ground->vertices[t.z]);
            const double d = (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
            const double l1 = ((b.y - c.y) * (x - c.x) + (c.x - b.x) * (y - c.y)) / d;
            const double l2 = ((c.y - a.y) * (x - c.x) + (a.x - c.x) * (y - c.y)) / d;
            if (l1 >= -1e-9 && l2 >= -1e-9 && l1 + l2 <= 1 + 1e-9) return l1 * a.z + l2 * b.z + (1 - l1 - l2) * c.z;
        }
        FAIL("no ground under " << x << ", " << y);
        return 0.0;
    };
    // No vertex lies more than a few centimetres under the ground, and both tracks' four
    // bottom corners (eight vertices) lie on it.
    double deepest = 1e9;
    int touching = 0;
    for (const glm::vec3& v : tank->vertices) {
        const double gap = double(v.z) - groundAt(v.x, v.y);
        deepest = std::min(deepest, gap);
        touching += gap < 0.1;
    }
    CHECK(deepest > -0.15);
    CHECK(touching >= 8);
}

TEST_CASE("scene: the bundled demo scene matches its description") {
    const fs::path demo = io::demoScenePath();
    CHECK(demo == kAssets / "demo" / "scene.json");
    const core::Scene s = io::loadScene(demo);
    CHECK(s.origin == glm::dvec3(0.0));
    CHECK(s.skipped_triangles == 0);
    // Ground covers the 125 m disc of the paper's orbit with margin: 300 m x 300 m,
    // nearly flat (inside the 3 m RANSAC band), finely tessellated.
    const core::Bounds g = s.bounds(RoleMask::of({Role::Ground}));
    CHECK(g.lo.x <= -150.0);
    CHECK(g.lo.y <= -150.0);
    CHECK(g.hi.x >= 150.0);
    CHECK(g.hi.y >= 150.0);
    CHECK(g.size().z < 1.0);
    std::size_t ground_triangles = 0;
    for (const core::Mesh& m : s.meshes)
        if (m.role == Role::Ground) ground_triangles += m.triangles.size();
    CHECK(ground_triangles >= 2u * 150u * 150u);  // cells of 2 m or less
    // Tank-like target near the origin: 7 x 3.5 x 2.5 m plus its barrel.
    int targets = 0;
    for (const core::Mesh& m : s.meshes) {
        if (m.role != Role::Target) continue;
        ++targets;
        const core::Bounds t = meshBounds(m);
        CHECK(t.size().z == doctest::Approx(2.5).epsilon(0.02));
        CHECK(glm::length(glm::dvec2(t.centre())) < 3.0);
    }
    CHECK(targets == 1);
    // Buildings 6-15 m tall and trees: environment up to ~15 m.
    const core::Bounds e = s.bounds(RoleMask::of({Role::Environment}));
    CHECK(e.hi.z > 12.0);
    CHECK(e.hi.z < 20.0);
    CHECK(s.meshes.size() > 40);
}

TEST_CASE("scene: the hard and hilly scenes load") {
    const core::Scene hard = io::loadScene(kAssets / "hard" / "scene.json");
    CHECK(hard.hasRole(Role::Target));
    CHECK(hard.meshes.size() > 200);  // a dense forest
    const core::Bounds t = hard.bounds(RoleMask::of({Role::Target}));
    CHECK(t.size().y == doctest::Approx(3.5).epsilon(0.01));
    // Walls 8 m high or more stand 3.5 m from the street's axis on both sides of the tank.
    bool wall_left = false, wall_right = false;
    for (const core::Mesh& m : hard.meshes) {
        if (m.role != Role::Environment) continue;
        for (const glm::vec3& v : m.vertices) {
            if (std::abs(v.x) > 10.0f || v.z < 8.0f || std::abs(std::abs(v.y) - 3.5f) > 0.3f) continue;
            (v.y > 0 ? wall_left : wall_right) = true;
        }
    }
    CHECK(wall_left);
    CHECK(wall_right);

    const core::Scene hilly = io::loadScene(kAssets / "hilly" / "scene.json");
    const core::Bounds g = hilly.bounds(RoleMask::of({Role::Ground}));
    CHECK(g.size().z > 10.0);
    CHECK(g.size().z < 25.0);
    CHECK(g.size().x >= 300.0);
}
