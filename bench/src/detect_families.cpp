// bench/src/detect_families.cpp: leave one vehicle family out. The vehicles are
// scripts/make_vehicles.py's families (cars to tanks and towed guns); each family's first
// half of vehicles makes its training corpora, its second half its evaluation corpora, on
// flat and hilly ground (and, in the full configuration, the dense forest and the steep
// slopes), each item seen by the ideal sensor or one of the presets; the training items
// also from lower orbits and with fewer rays, so that the models learn vehicles at more
// point densities than the evaluation shows. The training items are
// described once (segments and features); a model per family learns from every other
// family's items, one more from all. Each family's evaluation clouds are then ranked by
// the model that never saw the family, the model that saw all, the shipped model and the
// clustering baseline, on the same clouds in the same run; and how well calibrated the
// models are there (Brier score, reliability table) on the families they never saw, and
// the precision-recall curves of all families pooled, drawn as an SVG picture.
#include "detect_families.hpp"

#include "common.hpp"
#include "detect_trained.hpp"

#include <core/error.hpp>
#include <detect/boosted_detector.hpp>
#include <detect/cluster_detector.hpp>
#include <detect/training.hpp>
#include <io/cloud_io.hpp>
#include <platform/atomic_file.hpp>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <sstream>
#include <thread>
#include <unistd.h>

namespace bench {
namespace {

namespace fs = std::filesystem;

// The two configurations: vehicles per family (half train, half evaluate), the scenes
// and items per scene and family of each side, and the views of each cloud.
struct FamilyConfig {
    int per_family;
    std::vector<std::string> train_scenes, eval_scenes;
    int train_items, eval_items, views;
};

FamilyConfig configFor(bool full) {
    if (full) return {12, {"demo", "hilly", "slopes"}, {"demo", "hilly", "hard", "slopes"}, 8, 3, 60};
    return {4, {"demo", "hilly"}, {"demo", "hilly"}, 3, 2, 16};
}

// A SPEC for a corpus of `scene` whose target is one of `files`: moved, turned, seen from
// varied orbits within the shorter-ranged preset's reach, by the ideal sensor or a preset.
nlohmann::json familySpec(const fs::path& assets, const std::string& scene, const std::vector<std::string>& files,
                          int count, std::uint64_t seed, int views, bool densities) {
    const int reach_m = scene == "slopes" ? 20 : 40;
    nlohmann::json spec = {{"scene", (assets / scene / "scene.json").string()},
                           {"count", count},
                           {"seed", seed},
                           {"vary",
                            {{"target_yaw_deg", {{"min", 0}, {"max", 360}}},
                             {"target_offset_m", {{"min", 0}, {"max", reach_m}}},
                             {"target_files", files},
                             {"environment_keep_fraction", {{"min", 0.6}, {"max", 1.0}}},
                             {"sensor_preset", {"ideal", "riegl-vux1uav", "livox-avia"}},
                             {"altitude_m", {{"min", 200}, {"max", 300}}},
                             {"alpha_deg", {{"min", 30}, {"max", 45}}},
                             {"views", views},
                             {"resolution", 128}}}};
    // Training across densities: lower orbits (denser clouds) and a quarter of the rays
    // (sparser ones) beside the evaluation's.
    if (densities) {
        spec["vary"]["altitude_m"] = {{"min", 100}, {"max", 300}};
        spec["vary"]["resolution"] = {64, 128};
    }
    return spec;
}

struct Family {
    std::string name;
    std::vector<std::string> train_files, eval_files;  // absolute mesh paths
    std::vector<fs::path> train_dirs, eval_dirs;       // their corpora
};

// Runs scripts/make_vehicles.py into DIR and groups its vehicles by family, the first
// half of each family for training and the rest for evaluation.
std::vector<Family> makeFamilies(const fs::path& dir, int per_family) {
    const std::string cmd = "python3 " + shellQuote((sourceRoot() / "scripts" / "make_vehicles.py").string()) +
                            " --out " + shellQuote(dir.string()) + " --per-family " + std::to_string(per_family) +
                            " --seed 1 >&2";
    if (std::system(cmd.c_str()) != 0) throw core::Error("bench detect: " + cmd + " failed");
    const nlohmann::json listing = nlohmann::json::parse(readText(dir / "vehicles.json"));
    std::vector<Family> out;
    std::map<std::string, std::size_t> at;
    std::map<std::string, int> seen;
    for (const nlohmann::json& v : listing.at("vehicles")) {
        const std::string family = v.at("family").get<std::string>();
        if (!at.count(family)) {
            at[family] = out.size();
            out.push_back({family, {}, {}, {}, {}});
        }
        Family& f = out[at[family]];
        const std::string file = (dir / v.at("file").get<std::string>()).string();
        (seen[family]++ < per_family / 2 ? f.train_files : f.eval_files).push_back(file);
    }
    return out;
}

struct Detectors {
    std::vector<std::shared_ptr<const detect::BoostedModel>> without;  // per family: trained on the others
    std::shared_ptr<const detect::BoostedModel> all;                   // trained on every family
};

// Describes every training item once and trains a model per family without it, and one
// on all; `report` receives the last (all families) training's report. With `models_dir`,
// each model is written there too (without_<family>.ldm, all.ldm).
Detectors trainModels(const std::vector<Family>& families, int threads, const fs::path& models_dir,
                      detect::TrainReport& report) {
    detect::TrainOptions to;
    to.boost.threads = threads;
    std::vector<std::vector<detect::TrainingItem>> items(families.size());
    std::vector<std::vector<std::string>> manifests(families.size());
    for (std::size_t f = 0; f < families.size(); ++f)
        for (const fs::path& dir : families[f].train_dirs) {
            const detect::CorpusListing l = detect::listCorpus(dir);
            manifests[f].push_back(l.manifest_sha256);
            for (std::size_t k = 0; k < l.ids.size(); ++k)
                items[f].push_back(detect::describeLabelledCloud(io::readCloud(l.cloud(k)), l.cloud(k).string(), to));
        }
    // A family's items are interleaved with the others' (item k of each family in turn),
    // so that the calibration's held-out fifth draws from every family.
    const auto gather = [&](std::size_t skip) {
        std::vector<detect::TrainingItem> chosen;
        std::vector<std::string> sha;
        std::size_t longest = 0;
        for (const auto& list : items) longest = std::max(longest, list.size());
        for (std::size_t k = 0; k < longest; ++k)
            for (std::size_t f = 0; f < items.size(); ++f)
                if (f != skip && k < items[f].size()) chosen.push_back(items[f][k]);
        for (std::size_t f = 0; f < items.size(); ++f)
            if (f != skip) sha.insert(sha.end(), manifests[f].begin(), manifests[f].end());
        return std::make_pair(std::move(chosen), std::move(sha));
    };
    Detectors d;
    for (std::size_t f = 0; f <= families.size(); ++f) {
        auto [chosen, sha] = gather(f);
        detect::TrainReport r;
        auto model = std::make_shared<const detect::BoostedModel>(detect::trainDetector(chosen, to, sha, r));
        std::fprintf(stderr, "bench detect: model %s: %zu items, %zu segments, %zu positives\n",
                     f < families.size() ? ("without " + families[f].name).c_str() : "of all families", r.items,
                     r.segments, r.positives);
        if (!models_dir.empty()) {
            fs::create_directories(models_dir);
            model->write(models_dir / (f < families.size() ? "without_" + families[f].name + ".ldm" : "all.ldm"));
        }
        if (f < families.size()) {
            d.without.push_back(std::move(model));
        } else {
            d.all = std::move(model);
            report = r;
        }
    }
    return d;
}

std::string pct(std::size_t a, std::size_t n) {
    return n ? fmt("%.0f %%", 100.0 * double(a) / double(n)) : std::string("n/a");
}

// One cell group: ranked 1st, top 3, false candidates per cloud at the 90 % threshold.
std::string cells(const Summary& s) {
    return pct(s.rank1, s.clouds) + " | " + pct(s.top3, s.clouds) + " | " +
           (s.threshold >= 0 ? fmt("%.2f", s.false_per_cloud) : std::string("not reached"));
}

// Calibration over every segment a detector scored (its probability against whether
// most of its points are the target): the Brier score and a reliability table in the
// bins the training report uses, [0, .1), [.1, .5), [.5, .9), [.9, 1].
struct Calibration {
    std::size_t segments = 0, targets = 0;
    double brier = 0;
    std::size_t count[4] = {0, 0, 0, 0};
    double mean_p[4] = {0, 0, 0, 0}, share[4] = {0, 0, 0, 0};
};

Calibration calibrate(const std::vector<Outcome>& outcomes) {
    Calibration c;
    for (const Outcome& o : outcomes)
        for (const auto& [p, tp] : o.scored) {
            const double y = tp ? 1.0 : 0.0;
            ++c.segments;
            c.targets += tp;
            c.brier += (p - y) * (p - y);
            const int bin = p < 0.1 ? 0 : p < 0.5 ? 1 : p < 0.9 ? 2 : 3;
            ++c.count[bin];
            c.mean_p[bin] += p;
            c.share[bin] += y;
        }
    if (c.segments) c.brier /= double(c.segments);
    for (int b = 0; b < 4; ++b)
        if (c.count[b]) c.mean_p[b] /= double(c.count[b]), c.share[b] /= double(c.count[b]);
    return c;
}

// A reliability row: detector, segments, targets, Brier, then per bin "mean p / target
// share (segments)".
std::string calibrationRow(const std::string& name, const Calibration& c) {
    std::string row = "| " + name + " | " + std::to_string(c.segments) + " | " + std::to_string(c.targets) + " | " +
                      fmt("%.4f", c.brier);
    for (int b = 0; b < 4; ++b)
        row += " | " + (c.count[b] ? fmt("%.3f", c.mean_p[b]) + " / " + fmt("%.3f", c.share[b]) + " (" +
                                         std::to_string(c.count[b]) + ")"
                                   : std::string("none"));
    return row + " |\n";
}

// printf into a string, for the picture's numbers.
template <class... Args>
std::string svgText(const char* format, Args... args) {
    char buffer[256];
    std::snprintf(buffer, sizeof buffer, format, args...);
    return buffer;
}

// One detector's curve: its name, colour and outcomes.
struct Curve {
    const char* name;
    const char* colour;
    const std::vector<Outcome>* outcomes;
};

// The precision-recall curves of `curves` as an SVG picture: recall along x, precision up
// y, a dot where each curve first finds 90 % of the targets with the false candidates per
// cloud there.
std::string prSvg(const std::vector<Curve>& curves, const std::string& title) {
    constexpr double kW = 640, kH = 440, kX0 = 60, kX1 = 620, kY0 = 30, kY1 = 390;
    const auto X = [&](double r) { return kX0 + r * (kX1 - kX0); };
    const auto Y = [&](double p) { return kY1 - p * (kY1 - kY0); };
    std::ostringstream s;
    s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kW << "\" height=\"" << kH
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << kW / 2 << "\" y=\"18\" text-anchor=\"middle\" font-size=\"13\">" << title << "</text>\n";
    for (int k = 0; k <= 5; ++k) {
        const double v = k / 5.0;
        s << svgText("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>", X(v), kY0, X(v), kY1)
          << svgText("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>", kX0, Y(v), kX1, Y(v))
          << svgText("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%.1f</text>", X(v), kY1 + 16, v)
          << svgText("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%.1f</text>\n", kX0 - 6, Y(v) + 4, v);
    }
    s << svgText("<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" stroke=\"black\"/>\n", kX0,
                 kY0, kX1 - kX0, kY1 - kY0)
      << svgText("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">", (kX0 + kX1) / 2, kY1 + 34)
      << "recall (share of clouds whose target a candidate at or above the threshold finds)</text>\n"
      << svgText("<text transform=\"translate(16 %.1f) rotate(-90)\" text-anchor=\"middle\">", (kY0 + kY1) / 2)
      << "precision (targets among the candidates at or above it)</text>\n";
    for (std::size_t c = 0; c < curves.size(); ++c) {
        const std::vector<PrPoint> pts = prCurve(*curves[c].outcomes);
        s << "<polyline fill=\"none\" stroke-width=\"2\" stroke=\"" << curves[c].colour << "\" points=\"";
        for (const PrPoint& p : pts) s << svgText("%.1f,%.1f ", X(p.recall), Y(p.precision));
        s << "\"/>\n";
        for (const PrPoint& p : pts)
            if (p.recall >= 0.9) {
                s << svgText("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"", X(p.recall), Y(p.precision))
                  << curves[c].colour << "\"/>"
                  << svgText("<text x=\"%.1f\" y=\"%.1f\" fill=\"", X(p.recall) - 6,
                             Y(p.precision) - 6 - 12.0 * double(c))
                  << curves[c].colour << "\" text-anchor=\"end\">" << fmt("%.2f", p.false_per_cloud)
                  << " false per cloud</text>\n";
                break;
            }
        const double ly = Y(0.62) + 16.0 * double(c);
        s << svgText("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke-width=\"2\" stroke=\"", kX0 + 12, ly,
                     kX0 + 36, ly)
          << curves[c].colour << "\"/>" << svgText("<text x=\"%.1f\" y=\"%.1f\">", kX0 + 42, ly + 4) << curves[c].name
          << "</text>\n";
    }
    s << "</svg>\n";
    return s.str();
}

}  // namespace

std::string runFamilyComparison(const FamilyBenchOptions& o) {
    const FamilyConfig cfg = configFor(o.full);
    const fs::path assets = sourceRoot() / "assets";
    const WorkFolder work(o.tmp, "ladarvr-bench-families-");
    const fs::path& tmp = work.path();

    std::vector<Family> families = makeFamilies(tmp / "vehicles", cfg.per_family);
    std::size_t left_out = 0;
    for (std::size_t f = 0; f < families.size(); ++f) {
        Family& fam = families[f];
        for (std::size_t s = 0; s < cfg.train_scenes.size(); ++s) {
            const std::string name = "train_" + fam.name + "_" + cfg.train_scenes[s];
            fam.train_dirs.push_back(tmp / name);
            left_out += buildCorpus(writeSpec(tmp, name,
                                              familySpec(assets, cfg.train_scenes[s], fam.train_files, cfg.train_items,
                                                         7000 + 10 * f + s, cfg.views, true)),
                                    fam.train_dirs.back(), o.threads, true);
        }
        for (std::size_t s = 0; s < cfg.eval_scenes.size(); ++s) {
            const std::string name = "eval_" + fam.name + "_" + cfg.eval_scenes[s];
            fam.eval_dirs.push_back(tmp / name);
            left_out += buildCorpus(writeSpec(tmp, name,
                                              familySpec(assets, cfg.eval_scenes[s], fam.eval_files, cfg.eval_items,
                                                         8000 + 10 * f + s, cfg.views, false)),
                                    fam.eval_dirs.back(), o.threads, true);
        }
    }
    detect::TrainReport report;
    const auto t_train = Clock::now();
    const Detectors models = trainModels(families, o.threads, o.tmp.empty() ? fs::path() : tmp / "models", report);
    const double train_s = secondsSince(t_train);

    detect::BoostedOptions bo;
    bo.min_probability = 0.0;
    bo.max_candidates = 1000000;
    bo.threads = o.threads;
    const detect::BoostedDetector all(bo, models.all);
    std::unique_ptr<detect::BoostedDetector> shipped;
    if (!o.shipped_model.empty()) {
        detect::BoostedOptions so = bo;
        so.model = o.shipped_model;
        shipped = std::make_unique<detect::BoostedDetector>(so);
    }
    detect::ClusterOptions co;
    co.min_score = 0.0;
    co.max_candidates = 1000000;
    const detect::ClusterDetector baseline(co);

    // Per family and overall: without the family, with all, shipped, baseline.
    std::vector<std::vector<Outcome>> overall(4);
    std::ostringstream table;
    table << "| family held out | clouds | without it: 1st | top 3 | false per cloud at 90 % | all families: 1st | "
             "top 3 | false | shipped model: 1st | top 3 | false | baseline: 1st | top 3 | false |\n"
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    std::string rows, brier_rows;
    for (std::size_t f = 0; f < families.size(); ++f) {
        const detect::BoostedDetector without(bo, models.without[f]);
        std::vector<std::vector<Outcome>> outs(4);
        for (const fs::path& dir : families[f].eval_dirs) {
            const detect::CorpusListing l = detect::listCorpus(dir);
            for (std::size_t k = 0; k < l.ids.size(); ++k) {
                const core::PointCloud c = io::readCloud(l.cloud(k));
                const std::string name = dir.filename().string() + " " + l.ids[k];
                outs[0].push_back(evaluate(without, c, 1, name));
                outs[1].push_back(evaluate(all, c, 1, name));
                if (shipped) outs[2].push_back(evaluate(*shipped, c, 1, name));
                outs[3].push_back(evaluate(baseline, c, 1, name));
                std::fprintf(stderr, "bench detect: %s: without %s rank %d, all %d, baseline %d\n", name.c_str(),
                             families[f].name.c_str(), outs[0].back().rank, outs[1].back().rank, outs[3].back().rank);
            }
        }
        for (int d = 0; d < 4; ++d) overall[d].insert(overall[d].end(), outs[d].begin(), outs[d].end());
        const Calibration c0 = calibrate(outs[0]), c1 = calibrate(outs[1]);
        brier_rows += "| " + families[f].name + " | " + std::to_string(c0.segments) + " | " +
                      std::to_string(c0.targets) + " | " + fmt("%.4f", c0.brier) + " | " + fmt("%.4f", c1.brier) +
                      " |\n";
        const Summary s0 = summarise(outs[0]);
        rows += "| " + families[f].name + " | " + std::to_string(s0.clouds) + " | " + cells(s0) + " | " +
                cells(summarise(outs[1])) + " | " + (shipped ? cells(summarise(outs[2])) : "n/a | n/a | n/a") + " | " +
                cells(summarise(outs[3])) + " |\n";
    }
    const Summary t0 = summarise(overall[0]);
    table << "| **all families** | " << t0.clouds << " | " << cells(t0) << " | " << cells(summarise(overall[1]))
          << " | " << (shipped ? cells(summarise(overall[2])) : "n/a | n/a | n/a") << " | "
          << cells(summarise(overall[3])) << " |\n"
          << rows;

    std::string picture;
    if (!o.pr_svg.empty()) {
        fs::create_directories(o.pr_svg.parent_path());
        platform::writeFileAtomic(
            o.pr_svg,
            prSvg(shipped ? std::vector<Curve>{{"trained without the family", "#1f77b4", &overall[0]},
                                               {"trained on all families", "#2ca02c", &overall[1]},
                                               {"shipped model", "#7f7f7f", &overall[2]},
                                               {"clustering baseline", "#ff7f0e", &overall[3]}}
                          : std::vector<Curve>{{"trained without the family", "#1f77b4", &overall[0]},
                                               {"trained on all families", "#2ca02c", &overall[1]},
                                               {"clustering baseline", "#ff7f0e", &overall[3]}},
                  "Families held out: every evaluation cloud, pooled (" + std::to_string(t0.clouds) + " clouds)"));
        std::fprintf(stderr, "bench detect: precision-recall curves in %s\n", o.pr_svg.c_str());
        picture = "\nPrecision-recall curves over the " + std::to_string(t0.clouds) +
                  " evaluation clouds of all families pooled (each family's clouds scored by the model trained "
                  "without it; recall: the share of clouds whose target a candidate at or above the threshold finds; "
                  "precision: the share of those candidates that are the target; the dot: where 90 % are found, "
                  "with the false candidates per cloud there):\n\n![precision-recall, families held out](" +
                  o.pr_link + ")\n";
    }
    std::ostringstream s;
    s << (o.full ? "Full configuration" : "Small configuration (`--families small`: few items, 16 views a cloud)")
      << ": " << families.size() << " families of " << cfg.per_family
      << " vehicles (scripts/make_vehicles.py --seed 1; " << cfg.per_family / 2 << " train and "
      << cfg.per_family - cfg.per_family / 2 << " are evaluated, per family), training items per family and scene "
      << cfg.train_items << " (scenes";
    for (const std::string& n : cfg.train_scenes) s << " " << n;
    s << "), evaluation items per family and scene " << cfg.eval_items << " (scenes";
    for (const std::string& n : cfg.eval_scenes) s << " " << n;
    s << "), " << cfg.views
      << " views of 128 x 128 rays from 200 to 300 m up, each item seen by the ideal sensor or a preset; the "
         "training items also from lower orbits and with fewer rays (100 to 300 m up, 64 or 128 rays across: "
         "denser and sparser clouds). The model of "
      << "all families learned from " << report.items << " items (" << report.segments << " segments, "
      << report.positives << " target segments; held-out Brier score " << fmt("%.4f", report.brier) << "); the "
      << families.size() + 1 << " trainings took " << fmt("%.1f", train_s)
      << " s with the items' segments and features."
      << (left_out ? " " + std::to_string(left_out) + " items were left out (no free place for the target)."
                   : std::string())
      << "\n\n"
      << "Per family held out, on that family's evaluation clouds: the target ranked 1st, in the top 3, and the "
         "false candidates per cloud at the highest threshold that still finds 90 % of the targets, for the model "
         "trained without the family, the model trained on all families (other vehicles of the same family), the "
         "shipped model (assets/detect/model.ldm: the tank, an APC and a van) and the clustering baseline.\n\n"
      << table.str()
      << "\nCalibration on the families held out: every segment of the evaluation clouds above (the targets' "
         "and all others), its probability against whether most of its points are the target. The model "
         "trained without the family is scored on that family's clouds, so its rows are calibration on vehicles "
         "of a kind it never saw; the training's own held-out Brier score above is on items of the families it "
         "learned. Reliability: mean probability / share of targets (segments) per probability bin.\n\n"
         "| detector | segments | targets | Brier | p < 0.1 | 0.1-0.5 | 0.5-0.9 | p >= 0.9 |\n"
         "|---|---:|---:|---:|---|---|---|---|\n"
      << calibrationRow("without the family", calibrate(overall[0]))
      << calibrationRow("all families", calibrate(overall[1]))
      << (shipped ? calibrationRow("shipped model", calibrate(overall[2])) : std::string())
      << "\n| family held out | segments | targets | Brier, model without it | Brier, model of all families |\n"
         "|---|---:|---:|---:|---:|\n"
      << brier_rows << picture;
    return s.str();
}

}  // namespace bench
