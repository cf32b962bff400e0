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
// the precision-recall curves of all families pooled, drawn as an SVG picture. Real
// places (ISPRS test sites made scenes, detect_places.hpp) add training items on some
// sites and evaluation clouds on others; every evaluation cloud, thinned, measures the
// detector per band of point density on the target.
#include "detect_families.hpp"

#include "common.hpp"
#include "detect_places.hpp"
#include "detect_trained.hpp"

#include <core/error.hpp>
#include <detect/boosted_detector.hpp>
#include <detect/cluster_detector.hpp>
#include <detect/training.hpp>
#include <io/cloud_io.hpp>
#include <platform/atomic_file.hpp>

#include <nlohmann/json.hpp>

#include <array>
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

// The configurations: vehicles per family (half train, half evaluate), the scenes and
// items per scene and family of each side, the views of each cloud; the real places
// trained on and those evaluated on (never the same site), their items per place and
// family and the edge of their boxes; the dense evaluation items per family (100 to 150 m
// up, 256 rays across: the top of the density range); the families made (empty: all).
struct FamilyConfig {
    int per_family;
    std::vector<std::string> train_scenes, eval_scenes;
    int train_items, eval_items, views;
    std::vector<std::string> train_places, eval_places;
    int place_train_items, place_eval_items;
    double place_voxel_m;
    int dense_items;
    std::string families;
};

FamilyConfig configFor(const std::string& name) {
    if (name == "full")
        return {12,
                {"demo", "hilly", "slopes"},
                {"demo", "hilly", "hard", "slopes"},
                8,
                3,
                60,
                {"CSite2", "FSite5"},
                {"CSite3", "FSite8"},
                4,
                3,
                0.5,
                2,
                ""};
    if (name == "small")
        return {
            4, {"demo", "hilly"}, {"demo", "hilly"}, 3, 2, 16, {"CSite2", "FSite5"}, {"CSite3", "FSite8"}, 2, 1, 0.5, 0,
            ""};
    // "test": two families, one cloud of each kind, coarse boxes; seconds, figures not meaningful.
    return {2, {"demo"}, {"demo"}, 2, 1, 4, {"CSite3"}, {"CSite2"}, 1, 1, 2.0, 1, "car,tank"};
}

// The keep fractions the evaluation clouds are thinned to (1: the cloud as generated).
constexpr double kKeepFractions[] = {1.0, 0.3, 0.1, 0.03, 0.01};
// Each training cloud is also described thinned to these fractions of its points, so the
// models learn vehicles at the sparse end of the density range too.
constexpr double kTrainKeepFractions[] = {0.1, 0.02};

// A SPEC for a corpus of `scene` whose target is one of `files`: moved, turned, seen from
// varied orbits within the shorter-ranged preset's reach, by the ideal sensor or a preset.
nlohmann::json familySpec(const fs::path& assets, const std::string& scene, const std::vector<std::string>& files,
                          int count, std::uint64_t seed, int views, bool densities) {
    nlohmann::json spec = vehicleSpec((assets / scene / "scene.json").string(), files, count, seed, views, densities,
                                      scene == "slopes" ? 20 : 40);
    spec["vary"]["environment_keep_fraction"] = {{"min", 0.6}, {"max", 1.0}};
    return spec;
}

struct Family {
    std::string name;
    std::vector<std::string> train_files, eval_files;        // absolute mesh paths
    std::vector<fs::path> train_dirs, eval_dirs;             // their corpora (training: places too)
    std::vector<fs::path> place_eval_dirs, dense_eval_dirs;  // evaluation on real places, dense clouds
};

// Runs scripts/make_vehicles.py into DIR and groups its vehicles by family, the first
// half of each family for training and the rest for evaluation.
std::vector<Family> makeFamilies(const fs::path& dir, int per_family, const std::string& families) {
    const std::string cmd = "python3 " + shellQuote((sourceRoot() / "scripts" / "make_vehicles.py").string()) +
                            " --out " + shellQuote(dir.string()) + " --per-family " + std::to_string(per_family) +
                            (families.empty() ? std::string() : " --families " + shellQuote(families)) +
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
            out.push_back({family, {}, {}, {}, {}, {}, {}});
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

// Describes every training item once (as generated and thinned to kTrainKeepFractions)
// and trains a model per family without it, and one on all; `report` receives the last (all families) training's report. With `models_dir`,
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
            for (std::size_t k = 0; k < l.ids.size(); ++k) {
                const core::PointCloud c = io::readCloud(l.cloud(k));
                items[f].push_back(detect::describeLabelledCloud(c, l.cloud(k).string(), to));
                for (std::size_t t = 0; t < std::size(kTrainKeepFractions); ++t)
                    items[f].push_back(detect::describeLabelledCloud(
                        thinCloud(c, kTrainKeepFractions[t], 77 + 1000 * items[f].size() + t),
                        l.cloud(k).string() + " thinned to " + fmt("%g", kTrainKeepFractions[t]), to));
            }
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

// Builds every family's corpora: training (the synthetic scenes and the training places)
// and evaluation (the synthetic scenes, the evaluation places, the dense clouds). Returns
// the items left out (no free place for the target).
std::size_t buildFamilyCorpora(std::vector<Family>& families, const FamilyConfig& cfg,
                               const std::vector<RealPlace>& train_places, const std::vector<RealPlace>& eval_places,
                               const fs::path& tmp, int threads) {
    const fs::path assets = sourceRoot() / "assets";
    std::size_t left_out = 0;
    const auto build = [&](std::vector<fs::path>& dirs, const std::string& name, const nlohmann::json& spec) {
        dirs.push_back(tmp / name);
        left_out += buildCorpus(writeSpec(tmp, name, spec), dirs.back(), threads, true);
    };
    for (std::size_t f = 0; f < families.size(); ++f) {
        Family& fam = families[f];
        for (std::size_t s = 0; s < cfg.train_scenes.size(); ++s)
            build(fam.train_dirs, "train_" + fam.name + "_" + cfg.train_scenes[s],
                  familySpec(assets, cfg.train_scenes[s], fam.train_files, cfg.train_items, 7000 + 10 * f + s,
                             cfg.views, true));
        for (std::size_t s = 0; s < cfg.eval_scenes.size(); ++s)
            build(fam.eval_dirs, "eval_" + fam.name + "_" + cfg.eval_scenes[s],
                  familySpec(assets, cfg.eval_scenes[s], fam.eval_files, cfg.eval_items, 8000 + 10 * f + s, cfg.views,
                             false));
        for (std::size_t p = 0; p < train_places.size(); ++p)
            build(fam.train_dirs, "train_" + fam.name + "_place_" + train_places[p].name,
                  placeSpec(train_places[p], fam.train_files, cfg.place_train_items, 9000 + 10 * f + p, cfg.views, true,
                            40));
        for (std::size_t p = 0; p < eval_places.size(); ++p)
            build(fam.place_eval_dirs, "eval_" + fam.name + "_place_" + eval_places[p].name,
                  placeSpec(eval_places[p], fam.eval_files, cfg.place_eval_items, 9500 + 10 * f + p, cfg.views, false,
                            40));
        if (cfg.dense_items > 0) {
            nlohmann::json spec =
                familySpec(assets, "demo", fam.eval_files, cfg.dense_items, 8500 + 10 * f, cfg.views, false);
            spec["vary"]["altitude_m"] = {{"min", 100}, {"max", 150}};
            spec["vary"]["resolution"] = 256;
            build(fam.dense_eval_dirs, "evaldense_" + fam.name + "_demo", spec);
        }
    }
    return left_out;
}

// Outcomes per detector: 0 the model without the cloud's family, 1 the model of all
// families, 2 the shipped model, 3 the baseline.
using Outcomes4 = std::vector<std::vector<Outcome>>;

// What the evaluation gathers: per family, on the synthetic scenes and on the real
// places; per density band, the model without the family and the baseline on every
// evaluation cloud at each keep fraction, and how many of them of each kind (scene, real
// place, dense).
struct Ranked {
    std::vector<Outcomes4> scenes, places;
    BandOutcomes without_bands, baseline_bands;
    std::vector<std::array<std::size_t, 3>> band_kinds;
    std::size_t unmeasured = 0;  // clouds whose target had under 3 points: no area to measure
};

// The detectors of one family's clouds (shipped may be null).
struct FamilyDetectors {
    const detect::Detector* without;
    const detect::Detector* all;
    const detect::Detector* shipped;
    const detect::Detector* baseline;
};

// Ranks `c` (kind 0 scene, 1 real place, 2 dense) by the four detectors into `outs` (not
// for dense clouds), then the model without the family and the baseline on the cloud
// thinned to each keep fraction, by the target's measured density.
void rankCloud(const core::PointCloud& c, const std::string& name, int kind, const FamilyDetectors& d, Outcomes4* outs,
               Ranked& r, std::uint64_t seed) {
    if (outs) {
        (*outs)[0].push_back(evaluate(*d.without, c, 1, name));
        (*outs)[1].push_back(evaluate(*d.all, c, 1, name));
        if (d.shipped) (*outs)[2].push_back(evaluate(*d.shipped, c, 1, name));
        (*outs)[3].push_back(evaluate(*d.baseline, c, 1, name));
    }
    const double area_m2 = targetAreaM2(c);
    if (area_m2 < 1.0) {
        ++r.unmeasured;
        return;
    }
    for (std::size_t k = 0; k < std::size(kKeepFractions); ++k) {
        const bool whole = kKeepFractions[k] >= 1.0;
        const core::PointCloud thinned = whole ? core::PointCloud() : thinCloud(c, kKeepFractions[k], seed + k);
        const core::PointCloud& t = whole ? c : thinned;
        const std::size_t band = densityBand(double(targetPoints(t)) / area_m2);
        r.without_bands[band].push_back(whole && outs ? (*outs)[0].back() : evaluate(*d.without, t, 1, name));
        r.baseline_bands[band].push_back(whole && outs ? (*outs)[3].back() : evaluate(*d.baseline, t, 1, name));
        ++r.band_kinds[band][std::size_t(kind)];
    }
}

// Every family's evaluation clouds ranked (Ranked).
Ranked rankFamilies(const std::vector<Family>& families, const Detectors& models, const detect::BoostedOptions& bo,
                    const detect::Detector& all, const detect::Detector* shipped, const detect::Detector& baseline) {
    Ranked r;
    const std::size_t bands = densityBandNames().size();
    r.without_bands.resize(bands);
    r.baseline_bands.resize(bands);
    r.band_kinds.assign(bands, {0, 0, 0});
    std::uint64_t seed = 1;
    for (std::size_t f = 0; f < families.size(); ++f) {
        const detect::BoostedDetector without(bo, models.without[f]);
        const FamilyDetectors d{&without, &all, shipped, &baseline};
        r.scenes.emplace_back(4);
        r.places.emplace_back(4);
        const auto each = [&](const std::vector<fs::path>& dirs, int kind, Outcomes4* outs) {
            for (const fs::path& dir : dirs) {
                const detect::CorpusListing l = detect::listCorpus(dir);
                for (std::size_t k = 0; k < l.ids.size(); ++k) {
                    const std::string name = dir.filename().string() + " " + l.ids[k];
                    rankCloud(io::readCloud(l.cloud(k)), name, kind, d, outs, r, seed);
                    seed += 1000;
                    if (outs)
                        std::fprintf(stderr, "bench detect: %s: without %s rank %d, all %d, baseline %d\n",
                                     name.c_str(), families[f].name.c_str(), (*outs)[0].back().rank,
                                     (*outs)[1].back().rank, (*outs)[3].back().rank);
                }
            }
        };
        each(families[f].eval_dirs, 0, &r.scenes.back());
        each(families[f].place_eval_dirs, 1, &r.places.back());
        each(families[f].dense_eval_dirs, 2, nullptr);
    }
    return r;
}

// The four detectors' outcomes of every family pooled.
Outcomes4 pooled(const std::vector<Outcomes4>& per_family) {
    Outcomes4 all(4);
    for (const Outcomes4& outs : per_family)
        for (int d = 0; d < 4; ++d) all[d].insert(all[d].end(), outs[d].begin(), outs[d].end());
    return all;
}

// The per-family table: all families pooled first, then each family held out.
std::string familyTable(const std::vector<Family>& families, const std::vector<Outcomes4>& outs, bool shipped) {
    std::ostringstream table;
    table << "| family held out | clouds | without it: 1st | top 3 | false per cloud at 90 % | all families: 1st | "
             "top 3 | false | shipped model: 1st | top 3 | false | baseline: 1st | top 3 | false |\n"
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    const auto row = [&](const std::string& name, const Outcomes4& o) {
        const Summary s0 = summarise(o[0]);
        table << "| " << name << " | " << s0.clouds << " | " << cells(s0) << " | " << cells(summarise(o[1])) << " | "
              << (shipped ? cells(summarise(o[2])) : "n/a | n/a | n/a") << " | " << cells(summarise(o[3])) << " |\n";
    };
    row("**all families**", pooled(outs));
    for (std::size_t f = 0; f < families.size(); ++f) row(families[f].name, outs[f]);
    return table.str();
}

// The density table: per band of measured points/m² on the target, the clouds of each
// kind, the model without the family and the baseline.
std::string densityTable(const Ranked& r) {
    std::ostringstream t;
    t << "| points/m² on the target | clouds (scenes / real places / dense) | without the family: 1st | top 3 | "
         "false per cloud at 90 % | baseline: 1st | top 3 | false |\n"
         "|---|---|---:|---:|---:|---:|---:|---:|\n";
    for (std::size_t b = 0; b < densityBandNames().size(); ++b) {
        const std::array<std::size_t, 3>& k = r.band_kinds[b];
        if (r.without_bands[b].empty()) {
            t << "| " << densityBandNames()[b] << " | none | | | | | | |\n";
            continue;
        }
        t << "| " << densityBandNames()[b] << " | " << k[0] + k[1] + k[2] << " (" << k[0] << " / " << k[1] << " / "
          << k[2] << ") | " << cells(summarise(r.without_bands[b])) << " | " << cells(summarise(r.baseline_bands[b]))
          << " |\n";
    }
    return t.str();
}

// The configuration's paragraph.
std::string describeConfig(const std::string& name, const FamilyConfig& cfg, std::size_t families,
                           const detect::TrainReport& report, double train_s, std::size_t left_out) {
    std::ostringstream s;
    s << (name == "full"    ? "Full configuration"
          : name == "small" ? "Small configuration (`--families small`: few items, 16 views a cloud)"
                            : "Test configuration (`--families test`: two families, a cloud or two of each kind; "
                              "figures not meaningful)")
      << ": " << families << " families of " << cfg.per_family << " vehicles (scripts/make_vehicles.py --seed 1; "
      << cfg.per_family / 2 << " train and " << cfg.per_family - cfg.per_family / 2
      << " are evaluated, per family), training items per family and scene " << cfg.train_items << " (scenes";
    for (const std::string& n : cfg.train_scenes) s << " " << n;
    s << "), evaluation items per family and scene " << cfg.eval_items << " (scenes";
    for (const std::string& n : cfg.eval_scenes) s << " " << n;
    s << "), " << cfg.views
      << " views of 128 x 128 rays from 200 to 300 m up, each item seen by the ideal sensor or a preset; the "
         "training items also from lower orbits and with fewer rays (100 to 300 m up, 64 or 128 rays across: "
         "denser and sparser clouds), and each training cloud also thinned at random to keep";
    for (std::size_t k = 0; k < std::size(kTrainKeepFractions); ++k)
        s << (k ? " and " : " ") << fmt("%g", kTrainKeepFractions[k]);
    s << " of its points (each a training item of its own). Real places: training items per family and place "
      << cfg.place_train_items << " (";
    for (std::size_t k = 0; k < cfg.train_places.size(); ++k) s << (k ? ", " : "") << cfg.train_places[k];
    s << "), evaluation items per family and place " << cfg.place_eval_items << " (";
    for (std::size_t k = 0; k < cfg.eval_places.size(); ++k) s << (k ? ", " : "") << cfg.eval_places[k];
    s << "). The model of all families learned from " << report.items << " items (" << report.segments << " segments, "
      << report.positives << " target segments; held-out Brier score " << fmt("%.4f", report.brier) << "); the "
      << families + 1 << " trainings took " << fmt("%.1f", train_s) << " s with the items' segments and features."
      << (left_out ? " " + std::to_string(left_out) + " items were left out (no free place for the target)."
                   : std::string())
      << "\n\n";
    return s.str();
}

// The real places' paragraph: the sites, their own density, and how their scenes are made.
std::string describePlaces(const std::vector<RealPlace>& train, const std::vector<RealPlace>& eval, double voxel_m) {
    std::ostringstream s;
    const auto list = [&](const std::vector<RealPlace>& places) {
        for (std::size_t k = 0; k < places.size(); ++k)
            s << (k ? ", " : "") << places[k].name << " (" << fmt("%.1f", places[k].survey_points_per_m2)
              << " points/m², band " << densityBandNames()[densityBand(places[k].survey_points_per_m2)] << ")";
    };
    s << "**Real places as clutter.** ISPRS filter test sites (tests/data/real) made scenes as `ladarvr scene "
         "from-cloud` makes them (ground by SMRF as a terrain mesh, the other points as boxes of "
      << fmt("%g", voxel_m)
      << " m: their buildings, trees and cars), each family's vehicles moved on their ground among the boxes "
         "(`\"placement\": \"triangles\"`), seen by the same sensors and orbits. Every model trained on ";
    list(train);
    s << " and is evaluated on ";
    list(eval);
    s << ": no evaluation cloud comes from a site any model trained on. The densities in brackets are the surveys' "
         "own (points over the 2 m cells they cover), the density an ATR meets on such an airborne survey; the "
         "scenes made of them are seen by the simulated sensors at theirs.\n\n";
    return s.str();
}

}  // namespace

std::string runFamilyComparison(const FamilyBenchOptions& o) {
    const FamilyConfig cfg = configFor(o.configuration);
    const WorkFolder work(o.tmp, "ladarvr-bench-families-");
    const fs::path& tmp = work.path();

    std::vector<Family> families = makeFamilies(tmp / "vehicles", cfg.per_family, cfg.families);
    std::vector<RealPlace> train_places, eval_places;
    const fs::path tank = sourceRoot() / "assets" / "common" / "tank.obj";
    for (const std::string& p : cfg.train_places)
        train_places.push_back(makeRealPlace(p, tmp / ("place_" + p), tank, cfg.place_voxel_m, 1));
    for (const std::string& p : cfg.eval_places)
        eval_places.push_back(makeRealPlace(p, tmp / ("place_" + p), tank, cfg.place_voxel_m, 1));
    const std::size_t left_out = buildFamilyCorpora(families, cfg, train_places, eval_places, tmp, o.threads);
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
    const Ranked ranked = rankFamilies(families, models, bo, all, shipped.get(), baseline);
    const Outcomes4 overall = pooled(ranked.scenes);

    std::string brier_rows;
    for (std::size_t f = 0; f < families.size(); ++f)
        brier_rows += "| " + families[f].name + " | " + std::to_string(calibrate(ranked.scenes[f][0]).segments) +
                      " | " + std::to_string(calibrate(ranked.scenes[f][0]).targets) + " | " +
                      fmt("%.4f", calibrate(ranked.scenes[f][0]).brier) + " | " +
                      fmt("%.4f", calibrate(ranked.scenes[f][1]).brier) + " |\n";
    const Summary t0 = summarise(overall[0]);
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
    s << describeConfig(o.configuration, cfg, families.size(), report, train_s, left_out)
      << "Per family held out, on that family's evaluation clouds: the target ranked 1st, in the top 3, and the "
         "false candidates per cloud at the highest threshold that still finds 90 % of the targets, for the model "
         "trained without the family, the model trained on all families (other vehicles of the same family), the "
         "shipped model (assets/detect/model.ldm, scripts/train_shipped_model.sh) and the clustering baseline. The "
         "goal: for every family held out, 1st in at least 90 % of clouds, in the top 3 in at least 98 %, at most 1 "
         "false candidate per cloud at 90 %; the same on the real places.\n\n"
      << familyTable(families, ranked.scenes, shipped != nullptr) << "\n"
      << describePlaces(train_places, eval_places, cfg.place_voxel_m)
      << "Per family held out, on that family's evaluation clouds of the real places it never saw:\n\n"
      << familyTable(families, ranked.places, shipped != nullptr) << "\n"
      << "**Across densities.** Every evaluation cloud above (scenes and real places), and per family "
      << cfg.dense_items
      << " dense ones (the demo scene from 100 to 150 m up, 256 x 256 rays: not in the tables above), thinned at "
         "random to keep";
    for (std::size_t k = 0; k < std::size(kKeepFractions); ++k) s << (k ? ", " : " ") << fmt("%g", kKeepFractions[k]);
    s << " of its points, and ranked by the model trained without its family and by the baseline; each cloud "
         "falls in the band of its measured density on the target: its target's points over the area of their "
         "hull seen from above in the whole cloud (points/m²)."
      << (ranked.unmeasured ? " " + std::to_string(ranked.unmeasured) +
                                  " clouds whose target had under 3 points are left out (no area to measure)."
                            : std::string())
      << "\n\n"
      << densityTable(ranked)
      << "\nCalibration on the families held out: every segment of the evaluation clouds of the scenes (the "
         "targets' and all others), its probability against whether most of its points are the target. The model "
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
