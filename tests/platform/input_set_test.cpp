// tests/platform/input_set_test.cpp: a run's inputs (platform/input_set.hpp): files known by
// device and inode whatever name reaches them, folders that refuse outputs inside them but
// where their rule allows, and nothing remembered but what the set was given.
#include <test_files.hpp>
#include <platform/atomic_file.hpp>
#include <platform/input_set.hpp>

#include <doctest/doctest.h>

#include <filesystem>
#include <string>

namespace fs = std::filesystem;
using test_support::errorOf;
using test_support::TempDir;

TEST_CASE("input set: a file is refused as an output under any name that reaches it") {
    const TempDir dir("input_set_file");
    const fs::path scene = dir.write("scene.json", "{}");
    const fs::path other = dir.write("other.json", "{}");
    fs::create_hard_link(scene, dir.path / "hard.json");
    fs::create_symlink(scene, dir.path / "link.json");
    platform::InputSet inputs;
    inputs.addFile(scene);
    inputs.addFile(dir.path / "hard.json");  // the same file: listed once
    inputs.addFile(dir.path / "absent.json");
    const std::string expected = "output: " + (dir.path / "hard.json").string() + ": is the input file '" +
                                 scene.string() + "' of this run; give another name";
    CHECK(errorOf([&] { inputs.checkNotAnInput(dir.path / "hard.json"); }) == expected);
    CHECK(errorOf([&] { inputs.checkNotAnInput(dir.path / "link.json"); }).find("is the input file") !=
          std::string::npos);
    CHECK(errorOf([&] { platform::checkWritableDestination(scene, inputs); }).find("is the input file") !=
          std::string::npos);
    // Neither another file nor a name that did not exist when it was added.
    CHECK_NOTHROW(inputs.checkNotAnInput(other));
    CHECK_NOTHROW(inputs.checkNotAnInput(dir.path / "absent.json"));
    // A file read but not added is no input: the set holds what the command gives it.
    CHECK_NOTHROW(platform::InputSet().checkNotAnInput(scene));
    CHECK_NOTHROW(platform::checkWritableDestination(scene));
}

TEST_CASE("input set: a folder refuses outputs inside it except where its rule allows") {
    const TempDir dir("input_set_folder");
    fs::create_directories(dir.path / "corpus" / "items");
    fs::create_symlink(dir.path / "corpus", dir.path / "linked");
    platform::InputSet inputs;
    inputs.addFolder(dir.path / "corpus", [](const std::string& rel) { return rel == "histogram.png"; });
    inputs.addFolder(dir.path / "absent", {});
    CHECK(errorOf([&] { inputs.checkNotAnInput(dir.path / "corpus" / "items" / "a.pcd"); }) ==
          "output: " + (dir.path / "corpus" / "items" / "a.pcd").string() +
              ": is 'items/a.pcd' inside the input folder '" + (dir.path / "corpus").string() +
              "' of this run, which this command reads; give another name");
    CHECK(errorOf([&] {
              inputs.checkNotAnInput(dir.path / "linked" / "manifest.jsonl");
          }).find("is 'manifest.jsonl' inside the input folder") != std::string::npos);
    CHECK(errorOf([&] { inputs.checkNotAnInput(dir.path / "corpus"); }).find("is '.' inside") != std::string::npos);
    CHECK_NOTHROW(inputs.checkNotAnInput(dir.path / "corpus" / "histogram.png"));
    CHECK_NOTHROW(inputs.checkNotAnInput(dir.path / "beside.png"));
    CHECK_NOTHROW(inputs.checkNotAnInput(dir.path / "absent" / "x.png"));
}
