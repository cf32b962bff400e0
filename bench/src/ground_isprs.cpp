// bench/src/ground_isprs.cpp: `ladarvr bench ground-isprs`: the whole-cloud ground filters
// (sim/ground.hpp) on the ISPRS filter-test reference samples (Sithole and Vosselman 2004:
// 15 real airborne samples, hand-labelled bare earth), scored as every paper on them does:
// per sample type I (bare earth called object / bare earth), type II (object called bare
// earth / object), total error (misclassified / all) and Cohen's kappa, then the means over
// the samples, beside the published figures. One parameter set for all samples per
// configuration: SMRF and CSF with their defaults, what `ladarvr ground` runs by default,
// and SMRF refined by learned trees (sim/ground_learned.hpp) scored leave-one-site-out
// (ground_isprs_learned.hpp); `--learned-variants` scores its feature sets and depths;
// `--adaptive-grid` scores SMRF's options chosen per sample, by the oracle and by a rule
// on the survey's traits fitted leave-one-site-out (ground_isprs_adaptive.hpp);
// `--selector` scores a few option sets chosen per tile by learned trees, leave-one-site-out
// (ground_isprs_selector.hpp), with `--selector-refine` the learned refinement on top;
// `--multiscale` scores multiscale surface filters (MCC, a residual pyramid) and each on
// SMRF's answer (ground_isprs_mcc.hpp).
// `--try` adds configurations to compare (printed only); `--map` draws where one errs
// (ground_isprs_map.hpp). Rewrites the section "## Ground filters on ISPRS samples (ladarvr
// bench ground-isprs)" of BENCHMARKS.md and the picture of `ladarvr ground`'s errors beside it
// (docs/img/ground_isprs_errors.png).
#include "common.hpp"
#include "ground_isprs_adaptive.hpp"
#include "ground_isprs_learned.hpp"
#include "ground_isprs_map.hpp"
#include "ground_isprs_mcc.hpp"
#include "ground_isprs_selector.hpp"
#include "ground_score.hpp"
#include "register.hpp"

#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/png.hpp>
#include <platform/atomic_file.hpp>
#include <sim/ground.hpp>
#include <sim/ground_file.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

namespace bench {
namespace {

namespace fs = std::filesystem;

const char* const kHeading = "## Ground filters on ISPRS samples (ladarvr bench ground-isprs)";

// The 15 reference samples, in the order papers list them.
const char* const kSamples[] = {"samp11", "samp12", "samp21", "samp22", "samp23", "samp24", "samp31", "samp41",
                                "samp42", "samp51", "samp52", "samp53", "samp54", "samp61", "samp71"};

struct GroundIsprsCli {
    std::string data;  // empty: tests/data/isprs in the checkout
    std::vector<std::string> tries;
    std::string md = "BENCHMARKS.md";
    bool no_md = false;
    std::string write_model;          // --write-model: the trees learned from all samples, to this file
    bool variants = false;            // --learned-variants: the feature sets and depths tried
    std::string grid_csv;             // --adaptive-grid: every sample over a grid of SMRF options, to this CSV
    std::string traits_csv;           // --adaptive-traits: every sample's survey traits, to this CSV
    bool selector = false;            // --selector: SMRF's option set chosen per tile by learned trees
    bool selector_refine = false;     // --selector-refine: the learned refinement on the selector's answer
    bool multiscale = false;          // --multiscale: MCC and the residual pyramid beside `ladarvr ground`
    std::vector<std::string> subset;  // --samples: only these samples (with --selector or --multiscale)
    std::string map;                  // --map: the error picture of the last --try (else the default's), to this PNG
};

// The error picture the bench writes beside its section of BENCHMARKS.md (docs/ground.md shows it).
const char* const kMapDocPath = "docs/img/ground_isprs_errors.png";
constexpr int kMapPanel_px = 300, kMapColumns = 5, kMapGap_px = 6;

// One filter configuration to score: a label and the options `ladarvr ground` takes.
struct Config {
    std::string name;
    sim::GroundFileOptions options;
    bool learned = false;  // the learned refinement scored leave-one-site-out
};

// Per-sample scores against the reference labels.
using Score = GroundScore;
Score score(const std::vector<std::uint8_t>& found, const std::vector<std::uint8_t>& truth) {
    return scoreGround(found, truth);
}

// "smrf:cell_m=0.5,slope=0.2" / "csf:cloth_m=0.5,rigidness=2" into a configuration.
Config parseTry(const std::string& spec) {
    const auto bad = [&](const std::string& why) {
        return core::Error("bench ground-isprs: --try '" + spec + "': " + why +
                           "; allowed smrf:KEY=V,... (cell_m slope window_m threshold_m scalar raised_segments "
                           "low_outlier_m sparse_openings reconstruct reconstruct_h_m "
                           "reconstruct_tol_m reconstruct_steps reconstruct_from_m reconstruct_to_m) or "
                           "csf:KEY=V,... (cloth_m rigidness threshold_m time_step iterations low_outlier_m)");
    };
    Config c;
    c.name = "--try " + spec;
    const std::size_t colon = spec.find(':');
    const std::string method = spec.substr(0, colon);
    c.options = sim::GroundFileOptions{};
    c.options.method = sim::parseGroundMethod(method, "bench ground-isprs: --try");
    if (c.options.method == sim::GroundMethod::Ransac) throw bad("RANSAC works per view, not on a file");
    std::string rest = colon == std::string::npos ? "" : spec.substr(colon + 1);
    std::stringstream words(rest);
    std::string kv;
    while (std::getline(words, kv, ',')) {
        const std::size_t eq = kv.find('=');
        if (eq == std::string::npos) throw bad("'" + kv + "' is not KEY=VALUE");
        const std::string key = kv.substr(0, eq);
        char* end = nullptr;
        const double v = std::strtod(kv.c_str() + eq + 1, &end);
        if (end == kv.c_str() + eq + 1 || *end != '\0') throw bad("'" + kv + "' has no number");
        sim::SmrfOptions& s = c.options.smrf;
        sim::CsfOptions& f = c.options.csf;
        const bool smrf = c.options.method == sim::GroundMethod::Smrf;
        if (key == "low_outlier_m")
            s.low_outlier_m = f.low_outlier_m = v;
        else if (smrf && key == "cell_m")
            s.cell_m = v;
        else if (smrf && key == "slope")
            s.slope = v;
        else if (smrf && key == "window_m")
            s.window_m = v;
        else if (smrf && key == "threshold_m")
            s.threshold_m = v;
        else if (smrf && key == "scalar")
            s.scalar = v;
        else if (smrf && key == "raised_segments")
            s.raised_segments = v != 0;
        else if (smrf && key == "sparse_openings")
            s.sparse_openings = v != 0;
        else if (smrf && key == "reconstruct")
            s.reconstruct = int(v);
        else if (smrf && key == "reconstruct_h_m")
            s.reconstruct_h_m = v;
        else if (smrf && key == "reconstruct_tol_m")
            s.reconstruct_tol_m = v;
        else if (smrf && key == "reconstruct_steps")
            s.reconstruct_steps = int(v);
        else if (smrf && key == "reconstruct_from_m")
            s.reconstruct_from_m = v;
        else if (smrf && key == "reconstruct_to_m")
            s.reconstruct_to_m = v;
        else if (!smrf && key == "cloth_m")
            f.cloth_m = v;
        else if (!smrf && key == "rigidness")
            f.rigidness = int(v);
        else if (!smrf && key == "threshold_m")
            f.threshold_m = v;
        else if (!smrf && key == "time_step")
            f.time_step = v;
        else if (!smrf && key == "iterations")
            f.iterations = int(v);
        else
            throw bad("unknown key '" + key + "'");
    }
    sim::validate(c.options);
    return c;
}

struct Sample {
    std::string name;
    std::vector<core::CloudPoint> points;
    std::vector<std::uint8_t> truth;  // 1 = bare earth
};

// The error picture of one configuration's labels on every sample (ground_isprs_map.hpp).
void writeErrorMap(const fs::path& path, const std::vector<Sample>& samples,
                   const std::vector<std::vector<std::uint8_t>>& found) {
    std::vector<MapImage> panels;
    for (std::size_t k = 0; k < samples.size(); ++k)
        panels.push_back(renderErrorPanel(samples[k].points, samples[k].truth, found[k], kMapPanel_px,
                                          std::string_view(samples[k].name).substr(4)));
    const MapImage image = mosaic(panels, kMapColumns, kMapGap_px);
    io::writePng(path, image.rgb, image.width, image.height, 3);
    std::fprintf(stderr, "bench ground-isprs: wrote %s (%d x %d)\n", path.string().c_str(), image.width, image.height);
}

Score meanScore(const std::vector<Score>& scores) {
    Score mean;
    for (const Score& x : scores) {
        mean.type1 += x.type1 / double(scores.size());
        mean.type2 += x.type2 / double(scores.size());
        mean.total += x.total / double(scores.size());
        mean.kappa += x.kappa / double(scores.size());
    }
    return mean;
}

// The learned refinement's feature sets and tree depths, each scored leave-one-site-out.
void learnedVariants(const std::vector<LearnedSample>& learned) {
    const std::size_t columns = sim::learnedFeatureNames().size();
    std::vector<std::size_t> neighbourhood;  // every column but SMRF's and its variants' (0..6)
    for (std::size_t c = 7; c < columns; ++c) neighbourhood.push_back(c);
    struct Variant {
        std::string name;
        TreeParams p;
    };
    std::vector<Variant> variants;
    {
        TreeParams p;
        p.left_out = neighbourhood;
        variants.push_back(
            {"terrain heights only (SMRF and its 3 variants, slope), depth " + std::to_string(p.max_depth), p});
    }
    for (const int depth : {4, 6, 8}) {
        TreeParams p;
        p.max_depth = depth;
        variants.push_back({"all features, depth " + std::to_string(depth), p});
    }
    {
        TreeParams p;
        p.rounds = 400;
        p.eta = 0.05;
        variants.push_back({"all features, depth " + std::to_string(p.max_depth) + ", 400 rounds of 0.05", p});
    }
    for (const Variant& v : variants) {
        const auto margins = leaveOneSiteOut(learned, v.p);
        for (const double confidence : {0.0, 1.0, 2.0, 3.0}) {
            std::vector<Score> scores;
            std::ostringstream per;
            for (std::size_t k = 0; k < learned.size(); ++k) {
                scores.push_back(score(refinedLabels(learned[k], margins[k], confidence), learned[k].truth));
                per << " " << learned[k].name << " " << fmt("%.2f", scores.back().total);
            }
            const Score m = meanScore(scores);
            std::printf(
                "learned, %s, SMRF changed where the trees' logit disagrees by over %.0f: mean type I %.2f, type II "
                "%.2f, total %.2f %%, kappa %.1f %% (leave-one-site-out;%s)\n",
                v.name.c_str(), confidence, m.type1, m.type2, m.total, m.kappa, per.str().c_str());
            std::fflush(stdout);
        }
    }
}

// The selector's table, and with `refine` the learned refinement (trees learned
// leave-one-site-out, as its own row) applied to the selector's answer instead of SMRF's.
void runSelectorStudy(const std::vector<Sample>& samples, bool refine) {
    std::vector<AdaptiveSample> adaptive;
    for (const Sample& sample : samples) adaptive.push_back({sample.name, &sample.points, &sample.truth});
    const std::vector<std::vector<std::uint8_t>> selected = runSelector(adaptive);
    if (!refine) return;
    std::vector<LearnedSample> learned;
    for (const Sample& sample : samples)
        learned.push_back(describeSample(sample.name, sample.points, sample.truth, sim::surveySmrfOptions()));
    const std::vector<std::vector<float>> margins = leaveOneSiteOut(learned, TreeParams{});
    std::vector<Score> alone, on_selector;
    std::ostringstream per;
    for (std::size_t k = 0; k < learned.size(); ++k) {
        alone.push_back(score(refinedLabels(learned[k], margins[k], kRefineConfidence), learned[k].truth));
        learned[k].smrf = selected[k];
        on_selector.push_back(score(refinedLabels(learned[k], margins[k], kRefineConfidence), learned[k].truth));
        per << " " << learned[k].name << " " << fmt("%.2f", on_selector.back().total);
    }
    const Score a = meanScore(alone), b = meanScore(on_selector);
    std::printf(
        "\nthe learned refinement on SMRF's answer: mean total %.2f %%, kappa %.1f %%; on the selector's "
        "answer: mean type I %.2f, type II %.2f, total %.2f %%, kappa %.1f %% (leave-one-site-out;%s)\n",
        a.total, a.kappa, b.type1, b.type2, b.total, b.kappa, per.str().c_str());
}

void run(const GroundIsprsCli& cli) {
    const fs::path dir = cli.data.empty() ? sourceRoot() / "tests" / "data" / "isprs" : fs::path(cli.data);
    if (!cli.map.empty()) {
        // A PNG name keeps the picture off every input (samples are .laz or .las) and off the section's file.
        if (fs::path(cli.map).extension() != ".png")
            throw core::Error("bench ground-isprs: --map '" + cli.map + "': allowed a file name ending in .png");
        if (fs::weakly_canonical(cli.map) == fs::weakly_canonical(cli.md))
            throw core::Error("bench ground-isprs: --map '" + cli.map + "' is the --md file; allowed another file");
    }
    // Each sample as LAZ (the copies in tests/data/isprs) or as LAS (the published files).
    for (const std::string& name : cli.subset)
        if (std::find_if(std::begin(kSamples), std::end(kSamples), [&](const char* k) { return name == k; }) ==
            std::end(kSamples))
            throw core::Error("bench ground-isprs: --samples: '" + name +
                              "' is not an ISPRS sample; allowed samp11, samp12, samp21 ... samp71");
    std::vector<fs::path> files;
    std::vector<const char*> names;
    for (const char* name : kSamples) {
        if (!cli.subset.empty() && std::find(cli.subset.begin(), cli.subset.end(), name) == cli.subset.end()) continue;
        names.push_back(name);
        const fs::path laz = dir / (std::string(name) + ".laz"), las = dir / (std::string(name) + ".las");
        if (!fs::is_regular_file(laz) && !fs::is_regular_file(las))
            throw core::Error("bench ground-isprs: --data " + dir.string() + ": no " + name +
                              ".laz or .las there; allowed a folder holding the 15 ISPRS samples samp11 ... samp71 "
                              "(.laz or .las)");
        files.push_back(fs::is_regular_file(laz) ? laz : las);
    }
    std::vector<Sample> samples;
    for (std::size_t k = 0; k < files.size(); ++k) {
        const char* name = names[k];
        core::PointCloud cloud = io::readCloud(files[k]);
        Sample s{name, std::move(cloud.points), {}};
        for (const core::CloudPoint& p : s.points) s.truth.push_back(p.label == core::Role::Ground ? 1 : 0);
        samples.push_back(std::move(s));
    }
    if (!cli.grid_csv.empty() || !cli.traits_csv.empty()) {
        std::vector<AdaptiveSample> adaptive;
        for (const Sample& sample : samples) adaptive.push_back({sample.name, &sample.points, &sample.truth});
        if (!cli.traits_csv.empty()) writeAdaptiveTraits(adaptive, cli.traits_csv);
        if (!cli.grid_csv.empty()) writeAdaptiveGrid(adaptive, cli.grid_csv);
        return;
    }
    if (cli.selector) {
        runSelectorStudy(samples, cli.selector_refine);
        return;
    }
    if (cli.multiscale) {
        std::vector<AdaptiveSample> adaptive;
        for (const Sample& sample : samples) adaptive.push_back({sample.name, &sample.points, &sample.truth});
        runMultiscale(adaptive);
        return;
    }
    std::vector<LearnedSample> learned;
    for (const Sample& sample : samples)
        learned.push_back(describeSample(sample.name, sample.points, sample.truth, sim::surveySmrfOptions()));
    if (cli.variants) {
        learnedVariants(learned);
        return;
    }
    if (!cli.write_model.empty()) {
        std::vector<const LearnedSample*> all_samples;
        for (const LearnedSample& l : learned) all_samples.push_back(&l);
        const sim::GroundModel model = learnGroundModel(all_samples, TreeParams{});
        const std::string text = sim::serializeGroundModel(model);
        sim::parseGroundModel(text, "bench ground-isprs: --write-model");  // reads back
        platform::writeFileAtomic(cli.write_model, text);
        std::fprintf(stderr, "bench ground-isprs: wrote %s (%zu trees, %zu bytes, learned from %zu samples)\n",
                     cli.write_model.c_str(), model.trees.size(), text.size(), all_samples.size());
        return;
    }
    const auto t_learned = Clock::now();
    const std::vector<std::vector<float>> learned_margins = leaveOneSiteOut(learned, TreeParams{});
    const double learned_seconds = secondsSince(t_learned);

    std::vector<Config> configs;
    {
        Config smrf{"SMRF, defaults (PDAL's)", {}};
        smrf.options.method = sim::GroundMethod::Smrf;
        smrf.options.smrf = sim::SmrfOptions{};
        Config csf{"CSF, defaults (the paper's)", {}};
        csf.options.method = sim::GroundMethod::Csf;
        csf.options.csf = sim::CsfOptions{};
        Config survey_csf{"`ladarvr ground --method csf`", sim::GroundFileOptions{}};
        survey_csf.options.method = sim::GroundMethod::Csf;
        Config learned_row{"SMRF refined by learned trees (leave-one-site-out)", sim::GroundFileOptions{}, true};
        configs = {smrf, csf, Config{"`ladarvr ground` (its default, SMRF)", sim::GroundFileOptions{}}, survey_csf,
                   learned_row};
    }
    const sim::GroundFileOptions survey_csf_options = configs[3].options;
    for (const std::string& t : cli.tries) configs.push_back(parseTry(t));

    std::ostringstream s;
    s << kHeading << "\n\n"
      << "`./ladarvr bench ground-isprs" << (cli.data.empty() ? "" : " --data " + cli.data) << "` on " << cpuName()
      << " (" << std::thread::hardware_concurrency() << " cores), " << utcNow()
      << ". The 15 ISPRS filter-test reference samples (Sithole and Vosselman 2004; real airborne "
         "lidar, hand-labelled bare earth), one parameter set for all samples per configuration. Type I: "
         "bare earth called object; type II: object called bare earth; total: misclassified / all; kappa: "
         "Cohen's. Percent. The learned refinement's figures are leave-one-site-out: each sample is classified by "
         "trees learned from the samples of the other six sites only (sites 1: samp11-12, 2: 21-24, 3: 31, 4: "
         "41-42, 5: 51-54, 6: 61, 7: 71), so they say how it does on a survey it never saw.\n\n";
    std::ostringstream means;
    means << "| configuration | mean type I | mean type II | mean total error | mean kappa | worst sample | s |\n"
          << "|---|---:|---:|---:|---:|---|---:|\n";
    std::ostringstream per;
    per << "| sample |";
    for (std::size_t c = 0; c < configs.size(); ++c) per << " " << configs[c].name << " |";
    per << " CSF published |\n|---|";
    for (std::size_t c = 0; c <= configs.size(); ++c) per << "---:|";
    per << "\n";
    std::vector<std::vector<Score>> all(configs.size());
    // The labels of `ladarvr ground`'s default (configs[2]) and of the last --try, for the
    // error pictures.
    std::vector<std::vector<std::uint8_t>> default_found, last_found;
    for (std::size_t c = 0; c < configs.size(); ++c) {
        const auto t0 = Clock::now();
        for (std::size_t k = 0; k < samples.size(); ++k) {
            std::vector<std::uint8_t> found = configs[c].learned
                                                  ? refinedLabels(learned[k], learned_margins[k], kRefineConfidence)
                                                  : sim::classifyGround(samples[k].points, configs[c].options);
            all[c].push_back(score(found, samples[k].truth));
            if (c == 2) default_found.push_back(found);
            if (c + 1 == configs.size() && !cli.tries.empty()) last_found.push_back(std::move(found));
        }
        const double seconds = configs[c].learned ? learned_seconds : secondsSince(t0);
        Score mean;
        std::size_t worst = 0;
        for (std::size_t k = 0; k < samples.size(); ++k) {
            const Score& x = all[c][k];
            mean.type1 += x.type1 / double(samples.size());
            mean.type2 += x.type2 / double(samples.size());
            mean.total += x.total / double(samples.size());
            mean.kappa += x.kappa / double(samples.size());
            if (x.total > all[c][worst].total) worst = k;
        }
        means << "| " << configs[c].name << " | " << fmt("%.2f", mean.type1) << " | " << fmt("%.2f", mean.type2)
              << " | " << fmt("%.2f", mean.total) << " | " << fmt("%.1f", mean.kappa) << " | " << samples[worst].name
              << " " << fmt("%.2f", all[c][worst].total) << " | " << fmt("%.2f", seconds) << " |\n";
        std::fprintf(stderr, "bench ground-isprs: %s: mean total error %.2f %%, kappa %.1f %% (%.2f s)\n",
                     configs[c].name.c_str(), mean.total, mean.kappa, seconds);
    }
    means << "| SMRF published (parameters per sample) | | | 2.97 | 90.0 | | |\n"
          << "| SMRF published (one set) | | | | 85.4 | | |\n"
          << "| CSF published (three parameter groups) | | | 4.39 | | | |\n";
    for (std::size_t k = 0; k < samples.size(); ++k) {
        per << "| " << samples[k].name << " |";
        for (std::size_t c = 0; c < configs.size(); ++c)
            per << " " << fmt("%.2f", all[c][k].type1) << " / " << fmt("%.2f", all[c][k].type2) << " / "
                << fmt("%.2f", all[c][k].total) << " / " << fmt("%.1f", all[c][k].kappa) << " |";
        per << " " << fmt("%.2f", csfPublishedTotal(samples[k].name)) << " |\n";
    }
    s << means.str() << "\nPer sample, type I / type II / total / kappa (CSF published: total):\n\n" << per.str();
    s << "\nWhat `ladarvr ground` runs by default: " << sim::describe(sim::GroundFileOptions{})
      << "; with `--method csf`: " << sim::describe(survey_csf_options) << ".\n";
    const bool rewrite = !cli.no_md && cli.tries.empty();
    if (rewrite)
        s << "\nWhere `ladarvr ground` errs on each sample (seen from above, numbered as the samples; grey: right, "
             "light on bare earth and darker on objects; red: bare earth called object, type I; blue: an object "
             "called bare earth, type II):\n\n![ladarvr ground's errors on the ISPRS samples]("
          << kMapDocPath << ")\n";
    std::printf("%s", s.str().c_str());
    const fs::path doc_map = sourceRoot() / kMapDocPath;
    // Without --try, --map asks for the picture the rewrite draws: one file is written once.
    if (!cli.map.empty() && !(rewrite && fs::weakly_canonical(cli.map) == fs::weakly_canonical(doc_map)))
        writeErrorMap(cli.map, samples, cli.tries.empty() ? default_found : last_found);
    if (rewrite) {
        writeErrorMap(doc_map, samples, default_found);
        replaceMarkdownSection(cli.md, kHeading, s.str());
    }
}

}  // namespace

void registerGroundIsprs(CLI::App& parent) {
    auto state = std::make_shared<GroundIsprsCli>();
    CLI::App* c = parent.add_subcommand(
        "ground-isprs",
        "ground filters (SMRF, CSF, `ladarvr ground`'s default) on the 15 ISPRS reference samples: type I, "
        "type II, total error and kappa against the published figures");
    c->add_option("--data", state->data,
                  "folder holding the 15 samples samp11 ... samp71 as .laz or .las (default: tests/data/isprs)");
    c->add_option("--try", state->tries,
                  "another configuration to score, from `ladarvr ground`'s defaults, e.g. smrf:cell_m=0.5,slope=0.2 "
                  "(printed only; BENCHMARKS.md "
                  "stays)");
    c->add_option("--md", state->md, "markdown file whose section is rewritten")->capture_default_str();
    c->add_flag("--no-md", state->no_md, "print only, leave BENCHMARKS.md alone");
    c->add_option("--write-model", state->write_model,
                  "learn the refinement's trees from all 15 samples (fixed seed) and write them to this file "
                  "(sim::loadGroundModel reads it; the program ships none), then stop");
    c->add_flag("--learned-variants", state->variants,
                "score the learned refinement's feature sets and tree depths leave-one-site-out, then stop");
    c->add_option("--adaptive-grid", state->grid_csv,
                  "score every sample over a grid of SMRF's cell, slope, window, threshold and scalar and write "
                  "the table to this CSV (the oracle the adaptive choice is measured against), then stop");
    c->add_option("--adaptive-traits", state->traits_csv,
                  "write every sample's survey traits (what the adaptive choice of SMRF's options reads) to this "
                  "CSV, then stop");
    CLI::Option* selector =
        c->add_flag("--selector", state->selector,
                    "score SMRF's option set chosen per tile by learned trees among a few sets, leave-one-site-out, "
                    "beside the per-tile oracle, then stop (prints only)");
    c->add_flag("--selector-refine", state->selector_refine,
                "with --selector: also the learned refinement applied to the selector's answer (learns its trees "
                "leave-one-site-out: minutes)")
        ->needs(selector);
    c->add_flag("--multiscale", state->multiscale,
                "score multiscale surface filters (MCC, a coarse-to-fine residual pyramid, each also on SMRF's "
                "answer) beside `ladarvr ground`, then stop (prints only)")
        ->excludes(selector);
    c->add_option("--map", state->map,
                  "also draw where the last configuration scored (the last --try, else `ladarvr ground`'s default) "
                  "errs on each sample, to this PNG (without --try or --no-md the bench draws the default's to "
                  "docs/img/ground_isprs_errors.png)");
    c->add_option("--samples", state->subset,
                  "with --selector or --multiscale: only these samples, e.g. samp24,samp41 (--selector: of at "
                  "least two sites)")
        ->delimiter(',');
    c->callback([state] {
        if (!state->subset.empty() && !state->selector && !state->multiscale)
            throw CLI::RequiresError("--samples", "--selector or --multiscale");
        // The picture comes from the main table's run, which these modes stop before.
        const std::pair<bool, const char*> modes[] = {{!state->write_model.empty(), "--write-model"},
                                                      {state->variants, "--learned-variants"},
                                                      {!state->grid_csv.empty(), "--adaptive-grid"},
                                                      {!state->traits_csv.empty(), "--adaptive-traits"},
                                                      {state->selector, "--selector"},
                                                      {state->multiscale, "--multiscale"}};
        for (const auto& [on, name] : modes)
            if (!state->map.empty() && on) throw CLI::ExcludesError("--map", name);
        run(*state);
    });
}

}  // namespace bench
