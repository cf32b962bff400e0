// bench/src/ground_real.cpp: `ladarvr bench ground-real`: how `ladarvr ground` agrees with
// the classes that real surveys' producers gave their points. The ISPRS samples'
// hand-labelled bare earth (`bench ground-isprs`) is the benchmark; this is the check a
// user makes on a survey of their own: tests/data/real's files whose producer classified
// the ground (class 2), or the files given with --in.
//
// Each file is read as `ladarvr ground` reads it (its units from its CRS, the options
// converted, the points in its ground frame) and classified with the default (SMRF) and
// with --method csf. A point counts where the producer decided it: not class 0 (never
// classified), 7 or 18 (noise) or 12 (overlap, which says nothing about the ground).
// Producer's class 2 against the rest: type I, type II, total error and kappa per file,
// then their means. The producers' rules are their own (a low-vegetation class at the
// ground's level, an unclassified class for what a stricter threshold left out), so the
// figures say where `ladarvr ground` differs from them, not which is right. Rewrites the
// section "## Ground against the producers' classes (ladarvr bench ground-real)" of
// BENCHMARKS.md unless --no-md.
#include "common.hpp"
#include "ground_score.hpp"
#include "register.hpp"

#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>
#include <sim/ground_file.hpp>
#include <sim/ground_units.hpp>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace bench {
namespace {

namespace fs = std::filesystem;

const char* const kHeading = "## Ground against the producers' classes (ladarvr bench ground-real)";

// tests/data/real's files whose producer classified the ground.
const char* const kFiles[] = {"4_6_crop.las", "sample_c.las", "hexbin-crop.las", "mvk-thin.las", "warsaw_small.las"};

struct GroundRealCli {
    std::vector<std::string> in;
    std::string md = "BENCHMARKS.md";
    bool no_md = false;
};

// Whether the producer decided a point of this class: ground (2) or something else.
bool decided(std::uint8_t c) { return c != 0 && c != 7 && c != 12 && c != 18; }

struct FileScore {
    std::string name, units;
    std::size_t points = 0, scored = 0, producer_ground = 0;
    GroundScore smrf, csf;
};

FileScore scoreFile(const fs::path& path) {
    FileScore f;
    f.name = path.filename().string();
    const sim::CoordinateUnits units = sim::readCoordinateUnits(path, "bench ground-real");
    f.units = sim::describe(units);
    io::CloudReader reader(path, io::SideRecords::Keep);
    core::PointCloud cloud = io::readCloud(reader);
    if (!cloud.foreign)
        throw core::Error("bench ground-real: " + path.string() +
                          ": holds no producer's classes (a cloud of ours, or not LAS/LAZ/COPC); allowed a LAS, LAZ "
                          "or COPC file from another producer with ground points (class 2)");
    const std::size_t stride = cloud.foreign->header.stride();
    std::vector<std::uint8_t> classes(cloud.points.size());
    for (std::size_t k = 0; k < cloud.points.size(); ++k) {
        core::ForeignPoint fp;
        std::memcpy(&fp, cloud.foreign->records.data() + k * stride, sizeof(fp));
        classes[k] = fp.classification;
    }
    // The frame `ladarvr ground` fits the points in: its raster's cells on the survey's lattice.
    sim::GroundFileOptions smrf = sim::inUnits(sim::GroundFileOptions{}, units);
    sim::GroundFileOptions csf = smrf;
    csf.method = sim::GroundMethod::Csf;
    sim::validate(smrf);
    sim::validate(csf);
    const glm::dvec3 shift = cloud.origin - sim::groundFrame(cloud.origin, smrf);
    for (core::CloudPoint& p : cloud.points) p.position += glm::vec3(shift);
    const std::vector<std::uint8_t> by_smrf = sim::classifyGround(cloud.points, smrf);
    const std::vector<std::uint8_t> by_csf = sim::classifyGround(cloud.points, csf);

    std::vector<std::uint8_t> truth, found_smrf, found_csf;
    for (std::size_t k = 0; k < classes.size(); ++k) {
        if (!decided(classes[k])) continue;
        truth.push_back(classes[k] == 2);
        found_smrf.push_back(by_smrf[k]);
        found_csf.push_back(by_csf[k]);
        f.producer_ground += classes[k] == 2;
    }
    f.points = cloud.points.size();
    f.scored = truth.size();
    if (f.producer_ground == 0)
        throw core::Error("bench ground-real: " + path.string() +
                          ": its producer classified no point as ground (class 2); allowed a survey whose ground "
                          "was classified");
    f.smrf = scoreGround(found_smrf, truth);
    f.csf = scoreGround(found_csf, truth);
    return f;
}

std::string cells(const GroundScore& s) {
    return fmt("%.2f", s.type1) + " | " + fmt("%.2f", s.type2) + " | " + fmt("%.2f", s.total) + " | " +
           fmt("%.1f", s.kappa);
}

void run(const GroundRealCli& cli) {
    std::vector<fs::path> files;
    if (cli.in.empty())
        for (const char* name : kFiles) files.push_back(sourceRoot() / "tests/data/real" / name);
    else
        for (const std::string& f : cli.in) files.emplace_back(f);
    std::vector<FileScore> scores;
    for (const fs::path& f : files) {
        std::fprintf(stderr, "bench ground-real: %s\n", f.string().c_str());
        scores.push_back(scoreFile(f));
    }
    std::ostringstream s;
    s << kHeading << "\n\n`./ladarvr bench ground-real";
    for (const std::string& f : cli.in) s << " --in " << shellQuote(f);
    s << "` on " << cpuName() << " (" << std::thread::hardware_concurrency() << " cores), " << utcNow()
      << ". Each file classified as `ladarvr ground` classifies it (its units from its CRS, the options "
         "converted), by the default (SMRF) and by `--method csf`, against its producer's classes: class 2 "
         "against every other class the producer decided (not 0, never classified; 7 and 18, noise; 12, "
         "overlap). Type I: the producer's ground called object; type II: the producer's other classes called "
         "ground; total: misclassified / scored; kappa: Cohen's. Percent. The producers' rules are their own, "
         "so these figures say where `ladarvr ground` differs from them, not which is right.\n\n";
    s << "| file | units | points | scored | producer's ground | SMRF type I | type II | total | kappa | CSF type I "
         "| type II | total | kappa |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    GroundScore mean_smrf, mean_csf;
    const double n = double(scores.size());
    for (const FileScore& f : scores) {
        s << "| " << f.name << " | " << f.units << " | " << f.points << " | " << f.scored << " | " << f.producer_ground
          << " | " << cells(f.smrf) << " | " << cells(f.csf) << " |\n";
        for (auto [mean, one] : {std::pair{&mean_smrf, &f.smrf}, std::pair{&mean_csf, &f.csf}}) {
            mean->type1 += one->type1 / n;
            mean->type2 += one->type2 / n;
            mean->total += one->total / n;
            mean->kappa += one->kappa / n;
        }
    }
    s << "| mean | | | | | " << cells(mean_smrf) << " | " << cells(mean_csf) << " |\n";
    std::printf("%s", s.str().c_str());
    if (!cli.no_md) {
        replaceMarkdownSection(cli.md, kHeading, s.str());
        std::fprintf(stderr, "bench ground-real: wrote the section to %s\n", cli.md.c_str());
    }
}

}  // namespace

void registerGroundReal(CLI::App& parent) {
    auto cli = std::make_shared<GroundRealCli>();
    CLI::App* c = parent.add_subcommand(
        "ground-real", "how `ladarvr ground` (SMRF, and --method csf) agrees with real surveys' producers' classes");
    c->add_option("--in", cli->in,
                  "LAS/LAZ/COPC files from other producers with ground classified (class 2); default: "
                  "tests/data/real's five such files");
    c->add_option("--md", cli->md, "markdown file whose ground-real section is rewritten")->capture_default_str();
    c->add_flag("--no-md", cli->no_md, "print only, leave BENCHMARKS.md alone");
    c->callback([cli] { run(*cli); });
}

}  // namespace bench
