// tests/safety/input_messages_test.cpp: scene JSON, viewer scripts, study plans and
// candidate files from a hostile user: duplicate keys, NUL characters, empty names,
// special files, binary bytes, oversized files and values, terminal escapes in labels,
// coordinates past any world frame. Each gives one line naming the place and what is
// allowed, and what is echoed of them is printable.
#include <test_files.hpp>
#include <test_paths.hpp>
#include <core/error.hpp>
#include <io/candidates_file.hpp>
#include <io/scene_file.hpp>
#include <study/plan.hpp>
#include <viewer/viewer.hpp>

#include <doctest/doctest.h>

#include <fstream>
#include <functional>
#include <string>

#include <sys/stat.h>

namespace fs = std::filesystem;
using test_support::TempDir;

using test_support::errorOf;

namespace {

const fs::path kBasic = fs::path(test_support::dataDir()) / "scenes" / "basic";

std::string sceneError(const std::string& json) {
    return errorOf([&] { io::loadSceneJson(json, kBasic / "test.json"); });
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

bool oneLine(const std::string& s) { return s.find('\n') == std::string::npos && s.size() < 1000; }

}  // namespace

TEST_CASE("scene JSON: a key given twice is refused, naming the object") {
    const std::string top = sceneError(R"({"meshes": [], "meshes": [{"file": "box.obj", "role": "target"}]})");
    CHECK(contains(top, "duplicate key 'meshes'; allowed: each key once per object"));
    const std::string entry = sceneError(R"({"meshes": [{"file": "ground.obj", "role": "ground"},
                                  {"file": "nope.obj", "file": "box.obj", "role": "target"}]})");
    CHECK(contains(entry, "test.json: meshes[1]: duplicate key 'file'"));
    CHECK(contains(sceneError(R"({"meshes": [{"file": "box.obj", "role": "target", "position": [0, 0, 0],
                                              "role": "ground"}]})"),
                   "meshes[0]: duplicate key 'role'"));
    // The same key in two different objects is fine.
    CHECK_NOTHROW(io::loadSceneJson(R"({"meshes": [{"file": "box.obj", "role": "target"},
                                                      {"file": "box.obj", "role": "environment"}]})",
                                    kBasic / "test.json"));
}

TEST_CASE("scene JSON: a NUL character in a name is refused, not cut short") {
    const std::string value = sceneError(R"({"meshes": [{"file": "box.obj\u0000junk", "role": "target"}]})");
    CHECK(contains(value, "meshes[0].file: the string 'box.obj\\x00junk' holds a NUL character"));
    CHECK(oneLine(value));
    const std::string key = sceneError(R"({"meshes": [{"file": "box.obj", "ro\u0000le": "target"}]})");
    CHECK(contains(key, "meshes[0]: a key holds a NUL character"));
    CHECK(contains(sceneError(R"({"comment": "a\u0000b", "meshes": []})"), "comment: the string"));
}

TEST_CASE("scene JSON: an empty file name says it is empty") {
    CHECK(contains(sceneError(R"({"meshes": [{"file": "", "role": "target"}]})"),
                   "meshes[0]: 'file' is an empty string; allowed: a mesh file name relative to the scene file"));
    CHECK(contains(sceneError(R"({"meshes": [{"file": 3, "role": "target"}]})"),
                   "'file' must be a non-empty string (a mesh file relative to the scene file), not a number"));
}

TEST_CASE("scene files and mesh files that are not regular files are named for what they are") {
    TempDir dir("scene_kinds");
    auto load = [](const fs::path& p) { return errorOf([&] { io::loadScene(p); }); };
    fs::create_symlink("loop.json", dir.path / "loop.json");
    CHECK(contains(load(dir.path / "loop.json"), "the scene file is a symbolic link loop"));
    fs::create_symlink("gone.json", dir.path / "dangling.json");
    CHECK(contains(load(dir.path / "dangling.json"), "the scene file is a dangling symbolic link"));
    const fs::path fifo = dir.path / "fifo.json";
    REQUIRE(::mkfifo(fifo.c_str(), 0666) == 0);
    CHECK(contains(load(fifo), "the scene file is a FIFO (named pipe); allowed: a regular file"));
    CHECK(contains(load(dir.path), "the scene file is a directory"));
    const fs::path huge = dir.path / "huge.json";
    { std::ofstream(huge) << "{"; }
    fs::resize_file(huge, io::kMaxSceneBytes + 1);
    CHECK(contains(load(huge), "the scene file is " + std::to_string(io::kMaxSceneBytes + 1) + " bytes"));
    // A mesh that is a FIFO: refused before Assimp would block on it.
    REQUIRE(::mkfifo((dir.path / "mesh.obj").c_str(), 0666) == 0);
    const fs::path scene = dir.write("scene.json", R"({"meshes": [{"file": "mesh.obj", "role": "target"}]})");
    CHECK(contains(load(scene), "mesh file '" + (dir.path / "mesh.obj").string() + "' is a FIFO (named pipe)"));
}

TEST_CASE("viewer scripts: regular files of at most 1 MiB, binary bytes never shown") {
    TempDir dir("scripts");
    auto read = [](const fs::path& p) { return errorOf([&] { viewer::readScript(p); }); };
    CHECK(contains(read("/dev/zero"), "view: --script /dev/zero: is a character device; allowed: a regular file"));
    CHECK(contains(read(dir.path), "is a directory"));
    const fs::path fifo = dir.path / "fifo";
    REQUIRE(::mkfifo(fifo.c_str(), 0666) == 0);
    CHECK(contains(read(fifo), "is a FIFO (named pipe)"));
    const fs::path binary = dir.write("binary", std::string("\x01\x02\xff\x1b[31m space\n", 13));
    const std::string m = read(binary);
    CHECK(contains(m, "line 1: frame (8 bytes, not shown) is not a whole number"));
    for (char c : m) CHECK_FALSE((static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f));
    const fs::path big = dir.write("big", std::string(viewer::kMaxScriptBytes + 1, '\n'));
    CHECK(contains(read(big), "bytes; allowed: a regular file of at most 1 MiB"));
    const fs::path good = dir.write("good", "# a comment\n10 space\n20 escape\n");
    CHECK(viewer::readScript(good).size() == 2);
}

TEST_CASE("study plans: a trial's name is shown escaped and capped, whatever the plan holds") {
    // A newline and ESC[2J (clear the screen) would reach stderr in "trial 1 of 1 (<name>)".
    const study::Plan plan = study::parsePlan(
        R"({"trials": [{"cloud": "a.pcd", "name": "one\ntwo\u001b[2J\u0085"},
                       {"cloud": "b.pcd", "name": "Pr\u00fcfung"}]})",
        "plan.json", ".");
    CHECK(plan.trials[0].name == "one\\x0atwo\\x1b[2J\\xc2\\x85");  // U+0085 is a C1 control
    CHECK(plan.trials[1].name == "Pr\u00fcfung");                   // UTF-8 text is text
    const std::string huge(1 << 20, 'n');
    const study::Plan big =
        study::parsePlan(R"({"trials": [{"cloud": "a.pcd", "name": ")" + huge + R"("}]})", "plan.json", ".");
    CHECK(big.trials[0].name.size() <= study::kMaxTrialNameChars + 3);
    CHECK(big.trials[0].name.ends_with("nnn..."));
    // The default name, the file's name, is no safer than a given one.
    const study::Plan unnamed = study::parsePlan(R"({"trials": [{"cloud": "dir/x\u001b[31m.pcd"}]})", "plan.json", ".");
    CHECK(unnamed.trials[0].name == "x\\x1b[31m.pcd");
}

TEST_CASE("candidate files: centres and sizes past any world frame are refused") {
    TempDir dir("candidates_range");
    auto read = [&](const std::string& centre, const std::string& size) {
        const fs::path file = dir.write("c.json", R"({"candidates": [{"id": "c1", "centre": )" + centre +
                                                      R"(, "size_m": )" + size + R"(, "score": 0.5}]})");
        return errorOf([&] { io::readCandidates(file); });
    };
    CHECK(contains(
        read("[1e300, 0, 0]", "[1, 1, 1]"),
        "candidates[0].centre[0] is 1e+300; allowed: [x, y, z] in world metres, each in [-1000000000, 1000000000]"));
    CHECK(contains(read("[0, 0, -1e10]", "[1, 1, 1]"), "candidates[0].centre[2] is -1e+10"));
    CHECK(contains(read("[0, 0, 0]", "[1, 1e300, 1]"), "candidates[0].size_m[1] is 1e+300"));
    // At the bound: still a box.
    CHECK(read("[1e9, -1e9, 0]", "[1e7, 1, 1]") == "(no error)");
}
