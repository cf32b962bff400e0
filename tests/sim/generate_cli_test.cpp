// tests/sim/generate_cli_test.cpp: the generator as `ladarvr generate` runs it, in child
// processes of the CLI: a run's peak RSS stays within --memory-mb, and the ground
// options' lines (the hint to use --ground smrf, refusals before any work). An executable
// of its own, so the generator's in-process tests build without the whole CLI.
#include <test_files.hpp>
#include <test_paths.hpp>

#include <io/scene_file.hpp>

#include <doctest/doctest.h>

#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <spawn.h>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <tuple>
#include <unistd.h>
#include <utility>
#include <vector>

extern char** environ;

namespace fs = std::filesystem;

namespace {

// Runs `args` as a child process; returns its exit status and, through `rss_kib`, its
// peak resident set (wait4's ru_maxrss).
int runChild(const std::vector<std::string>& args, long& rss_kib) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    pid_t pid = 0;
    REQUIRE(posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ) == 0);
    posix_spawn_file_actions_destroy(&actions);
    int status = 0;
    struct rusage usage{};
    REQUIRE(::wait4(pid, &status, 0, &usage) == pid);
    rss_kib = usage.ru_maxrss;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("peak RSS of `ladarvr generate` stays within --memory-mb (child processes)") {
#if defined(__SANITIZE_ADDRESS__)
    MESSAGE("skipped: AddressSanitizer's shadow memory and quarantine are not the program's");
    return;
#endif
    test_support::TempDir dir("rss");
    const auto generate = [&](const std::string& size, int views, const std::string& mib, long& rss_kib,
                              const char* out = "c.pcd") {
        return runChild({test_support::cliPath(), "generate", "--out", (dir.path / out).string(), "--xres", size,
                         "--yres", size, "--views", std::to_string(views), "--threads", "2", "--memory-mb", mib},
                        rss_kib);
    };
    long base = 0, roomy = 0, tight = 0, tight_laz = 0;
    // The process without the generator's buffers: libraries, scene, BVH.
    REQUIRE(generate("16", 1, "4096", base) == 0);
    REQUIRE(generate("1024", 4, "4096", roomy) == 0);
    REQUIRE(generate("1024", 4, "128", tight) == 0);
    // LAZ: chunks waiting for the compression threads come out of the same budget.
    REQUIRE(generate("1024", 4, "128", tight_laz, "c.laz") == 0);
    MESSAGE("peak RSS: base " << base / 1024 << " MiB, roomy " << roomy / 1024 << " MiB, --memory-mb 128 "
                              << tight / 1024 << " MiB, the same to LAZ " << tight_laz / 1024 << " MiB");
    CHECK(tight - base <= 128 * 1024);
    CHECK(tight_laz - base <= 128 * 1024);
    CHECK(roomy - base > 128 * 1024);  // without the budget the same run would exceed it
}

TEST_CASE("generate names --ground smrf when RANSAC leaves the bundled hilly scene's ground coloured") {
    const test_support::TempDir scratch("sim_ground_cli");
    const fs::path hilly = io::demoScenePath().parent_path().parent_path() / "hilly" / "scene.json";
    REQUIRE(fs::exists(hilly));
    const auto generate = [&](const std::string& method, const std::string& name) {
        const fs::path err = scratch.path / (name + ".err");
        const std::string command = std::string(test_support::cliPath()) + " generate --scene '" + hilly.string() +
                                    "' --out '" + (scratch.path / (name + ".pcd")).string() +
                                    "' --xres 96 --yres 64 --views 8 --threads 2 --ground " + method + " --dtm '" +
                                    (scratch.path / (name + ".asc")).string() + "' 2> '" + err.string() + "'";
        REQUIRE(std::system(command.c_str()) == 0);
        return test_support::slurp(err);
    };
    const std::string ransac = generate("ransac", "ransac");
    CHECK(ransac.find("--ground smrf") != std::string::npos);
    CHECK(ransac.find("RANSAC whitened only") != std::string::npos);
    const std::string smrf = generate("smrf", "smrf");
    CHECK(smrf.find("--ground smrf") == std::string::npos);
    CHECK(smrf.find("ground filter: smrf") != std::string::npos);
    CHECK(fs::file_size(scratch.path / "smrf.asc") > 1000);
    CHECK(fs::file_size(scratch.path / "ransac.asc") > 1000);
}

TEST_CASE("generate refuses an unknown --ground and a bad --smrf-* value before any work") {
    const test_support::TempDir scratch("sim_ground_cli_bad");
    const auto status = [&](const std::string& args) {
        const std::string command = std::string(test_support::cliPath()) + " generate --out '" +
                                    (scratch.path / "x.pcd").string() + "' " + args + " 2> '" +
                                    (scratch.path / "err").string() + "'";
        const int rc = std::system(command.c_str());
        return std::pair(WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, test_support::slurp(scratch.path / "err"));
    };
    auto [rc, err] = status("--ground pmf");
    CHECK(rc == 1);
    CHECK(err.find("--ground 'pmf': allowed ransac, smrf, csf") != std::string::npos);
    std::tie(rc, err) = status("--ground csf --csf-rigidness 5");
    CHECK(rc == 1);
    CHECK(err.find("--csf-rigidness") != std::string::npos);
    std::tie(rc, err) = status("--white --dtm '" + (scratch.path / "t.asc").string() + "'");
    CHECK(rc == 1);
    CHECK(err.find("--dtm: not with --white") != std::string::npos);
    CHECK_FALSE(fs::exists(scratch.path / "t.asc"));
    std::tie(rc, err) = status("--ground smrf --smrf-window-m -3");
    CHECK(rc == 1);
    CHECK(err.find("--smrf-window-m") != std::string::npos);
    CHECK_FALSE(fs::exists(scratch.path / "x.pcd"));
}
