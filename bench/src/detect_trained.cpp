// bench/src/detect_trained.cpp: the trained detector (detect/boosted_detector.hpp) against
// the clustering baseline (detect/cluster_detector.hpp), both on the same evaluation clouds.
//
// Training: the corpora of assets/detect/train_*.json (the tank, an APC and a van; flat and sloped
// village, seen by the ideal sensor and by the sensor presets). Evaluation, never seen in
// training:
//   - corpora of the demo (flat), hilly, hard (dense forest), slopes and forest scenes with
//     other seeds,
//     whose target is the tank or a box truck (assets/common/truck.obj, not in training),
//     each item seen by the ideal sensor or one of the presets (the corpus key
//     sensor_preset);
//   - the bundled demo, hilly, hard and forest scenes seen by each sensor preset but the
//     ideal one
//     (noise, footprints, several returns).
// Per cloud, the rank of the first true positive (a candidate most of whose points are
// labelled target) among all candidates; rank-1 and top-3 shares; the false candidates per
// cloud at the highest score threshold that still finds >= 90 % of the targets; and the
// detection time per cloud.
#include "detect_trained.hpp"

#include "common.hpp"

#include <core/error.hpp>
#include <corpus/run.hpp>
#include <detect/boosted_detector.hpp>
#include <detect/cluster_detector.hpp>
#include <detect/training.hpp>
#include <io/cloud_io.hpp>
#include <io/scene_file.hpp>
#include <platform/atomic_file.hpp>
#include <sim/generator.hpp>
#include <sim/sensor.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <sstream>
#include <unistd.h>

namespace bench {

namespace fs = std::filesystem;

namespace {

struct Cloud {
    std::string name;
    core::PointCloud cloud;
    bool ideal = true;  // seen by the ideal sensor (else by a preset)
};

}  // namespace

// Each item's sensor preset, from its manifest line's replay options (no --sensor: ideal).
std::map<std::string, std::string> sensorOfItems(const fs::path& dir) {
    std::map<std::string, std::string> out;
    std::istringstream lines(readText(dir / "manifest.jsonl"));
    for (std::string line; std::getline(lines, line);) {
        if (line.empty()) continue;
        const nlohmann::json j = nlohmann::json::parse(line);
        std::string sensor = "ideal";
        const auto& args = j.at("generate");
        for (std::size_t k = 0; k + 1 < args.size(); ++k)
            if (args[k] == "--sensor") sensor = args[k + 1].get<std::string>();
        out[j.at("id").get<std::string>()] = sensor;
    }
    return out;
}

// Detects `repeats` times; the time is the median, the candidates those of the first run,
// and every run must give the same candidates (detection is deterministic).
Outcome evaluate(const detect::Detector& d, const core::PointCloud& c, int repeats, const std::string& name) {
    Outcome o;
    std::vector<double> seconds;
    std::vector<detect::Detection> found;
    for (int r = 0; r < std::max(1, repeats); ++r) {
        const auto t0 = Clock::now();
        std::vector<detect::Detection> again = d.detect(c);
        seconds.push_back(secondsSince(t0));
        if (r == 0) {
            found = std::move(again);
            continue;
        }
        bool same = again.size() == found.size();
        for (std::size_t k = 0; same && k < found.size(); ++k)
            same = again[k].points == found[k].points && again[k].candidate.score == found[k].candidate.score;
        if (!same) throw core::Error("bench detect: " + name + ": a repeated detection gave other candidates");
    }
    o.seconds = median(seconds);
    o.seconds_min = *std::min_element(seconds.begin(), seconds.end());
    o.seconds_max = *std::max_element(seconds.begin(), seconds.end());
    for (std::size_t k = 0; k < found.size(); ++k) {
        std::size_t target = 0;
        for (const std::uint32_t i : found[k].points) target += c.points[i].label == core::Role::Target;
        const bool tp = 2 * target > found[k].points.size();
        if (tp && o.rank == 0) o.rank = int(k + 1);
        o.scored.push_back({found[k].candidate.score, tp});
    }
    return o;
}

Summary summarise(const std::vector<Outcome>& outcomes) {
    Summary s;
    s.clouds = outcomes.size();
    std::vector<double> times;
    // Candidates of all clouds by score; a cloud's target counts as found at a threshold
    // when its first true positive scores at least that; the other candidates above it
    // that are not true positives are false.
    struct Entry {
        double score;
        bool first_tp, tp;
    };
    std::vector<Entry> all;
    for (const Outcome& o : outcomes) {
        s.rank1 += o.rank == 1;
        s.top3 += o.rank >= 1 && o.rank <= 3;
        s.found += o.rank >= 1;
        times.push_back(o.seconds);
        for (std::size_t k = 0; k < o.scored.size(); ++k)
            all.push_back({o.scored[k].first, o.rank == int(k + 1), o.scored[k].second});
    }
    s.median_s = times.empty() ? 0 : median(times);
    s.max_s = times.empty() ? 0 : *std::max_element(times.begin(), times.end());
    std::stable_sort(all.begin(), all.end(), [](const Entry& a, const Entry& b) { return a.score > b.score; });
    const std::size_t need = (9 * s.clouds + 9) / 10;  // ceil(0.9 n)
    std::size_t found = 0, falses = 0;
    for (std::size_t k = 0; k < all.size(); ++k) {
        found += all[k].first_tp;
        falses += !all[k].tp;
        // Ties: the threshold takes every candidate of the same score.
        if (found >= need && need > 0 && (k + 1 == all.size() || all[k + 1].score < all[k].score)) {
            s.threshold = all[k].score;
            s.false_per_cloud = double(falses) / double(s.clouds);
            break;
        }
    }
    return s;
}

std::vector<PrPoint> prCurve(const std::vector<Outcome>& outcomes) {
    struct Entry {
        double score;
        bool first_tp, tp;
    };
    std::vector<Entry> all;
    for (const Outcome& o : outcomes)
        for (std::size_t k = 0; k < o.scored.size(); ++k)
            all.push_back({o.scored[k].first, o.rank == int(k + 1), o.scored[k].second});
    std::stable_sort(all.begin(), all.end(), [](const Entry& a, const Entry& b) { return a.score > b.score; });
    std::vector<PrPoint> out;
    std::size_t found = 0, tps = 0;
    for (std::size_t k = 0; k < all.size(); ++k) {
        found += all[k].first_tp;
        tps += all[k].tp;
        if (k + 1 < all.size() && all[k + 1].score == all[k].score) continue;
        out.push_back({all[k].score, double(tps) / double(k + 1), double(found) / double(outcomes.size()),
                       double(k + 1 - tps) / double(outcomes.size())});
    }
    return out;
}

namespace {

// The precision-recall curve of a detector over the clouds as CSV rows: detector,
// threshold, precision, recall, false candidates per cloud.
std::string prRows(const std::string& detector, const std::vector<Outcome>& outcomes) {
    std::ostringstream s;
    for (const PrPoint& p : prCurve(outcomes))
        s << detector << "," << fmt("%.6f", p.threshold) << "," << fmt("%.6f", p.precision) << ","
          << fmt("%.6f", p.recall) << "," << fmt("%.4f", p.false_per_cloud) << "\n";
    return s.str();
}

}  // namespace

fs::path writeSpec(const fs::path& dir, const std::string& name, nlohmann::json spec) {
    const fs::path path = dir / (name + ".json");
    platform::writeFileAtomic(path, spec.dump(2));
    return path;
}

// Builds a corpus; with allow_failed, items that cannot be planned (a target with no free
// place in a dense forest) are left out with a line each and their count returned.
std::size_t buildCorpus(const fs::path& spec, const fs::path& out, int threads, bool allow_failed) {
    corpus::RunOptions ro;
    ro.spec = spec;
    ro.out = out;
    ro.jobs = 1;
    ro.threads = threads;
    const corpus::RunSummary r = corpus::runCorpus(ro);
    if (!r.failed.empty() && !allow_failed)
        throw core::Error("bench detect: corpus " + out.string() + ": " + r.failed.front());
    for (const std::string& f : r.failed)
        std::fprintf(stderr, "bench detect: corpus %s: left out: %s\n", out.filename().string().c_str(), f.c_str());
    std::fprintf(stderr, "bench detect: corpus %s: %zu items\n", out.filename().string().c_str(), r.built + r.skipped);
    return r.failed.size();
}

std::string summaryRow(const char* name, const Summary& s) {
    std::ostringstream r;
    r << "| " << name << " | " << s.clouds << " | " << s.rank1 << " ("
      << fmt("%.0f", 100.0 * double(s.rank1) / double(std::max<std::size_t>(1, s.clouds))) << " %) | " << s.top3 << " ("
      << fmt("%.0f", 100.0 * double(s.top3) / double(std::max<std::size_t>(1, s.clouds))) << " %) | " << s.found
      << " | "
      << (s.threshold >= 0 ? fmt("%.3f", s.threshold) + " | " + fmt("%.2f", s.false_per_cloud)
                           : std::string("not reached | n/a"))
      << " | " << fmt("%.2f", s.median_s) << " | " << fmt("%.2f", s.max_s) << " |\n";
    return r.str();
}

std::string runTrainedComparison(const TrainedBenchOptions& o) {
    const fs::path root = sourceRoot();
    const fs::path assets = root / "assets";
    const WorkFolder work(o.tmp, "ladarvr-bench-detect-");
    const fs::path& tmp = work.path();

    // Training corpora: the shipped model's SPECs (smaller with --quick).
    std::vector<fs::path> train_dirs;
    for (const char* name : {"train_flat", "train_slopes", "train_flat_sensors", "train_slopes_sensors"}) {
        nlohmann::json spec = nlohmann::json::parse(readText(assets / "detect" / (std::string(name) + ".json")));
        spec["scene"] = (assets / "detect" / spec["scene"].get<std::string>()).lexically_normal().string();
        // The copy lives in the bench's folder: its target files' paths made absolute too.
        if (spec.contains("vary") && spec["vary"].contains("target_files"))
            for (nlohmann::json& f : spec["vary"]["target_files"]) {
                nlohmann::json& file = f.is_object() ? f["file"] : f;
                file = (assets / "detect" / file.get<std::string>()).lexically_normal().string();
            }
        if (o.quick) {
            spec["count"] = 2;
            spec["vary"]["views"] = 16;
        } else {
            spec["count"] = spec["count"].get<int>() * o.train_scale;
        }
        train_dirs.push_back(tmp / name);
        buildCorpus(writeSpec(tmp, name, spec), train_dirs.back(), o.threads);
    }
    detect::TrainOptions to;
    to.boost.threads = o.threads;
    std::vector<detect::TrainingItem> items;
    std::vector<std::string> manifests;
    for (const fs::path& dir : train_dirs) {
        const detect::CorpusListing l = detect::listCorpus(dir);
        manifests.push_back(l.manifest_sha256);
        for (std::size_t k = 0; k < l.ids.size(); ++k)
            items.push_back(detect::describeLabelledCloud(io::readCloud(l.cloud(k)), l.cloud(k).string(), to));
    }
    detect::TrainReport report;
    const auto t_train = Clock::now();
    auto model = std::make_shared<const detect::BoostedModel>(detect::trainDetector(items, to, manifests, report));
    const double train_s = secondsSince(t_train);

    // Evaluation clouds.
    std::vector<Cloud> clouds;
    std::size_t left_out = 0;  // evaluation items whose target could not be placed
    const int eval_count = o.quick ? 1 : o.eval_items;
    std::uint64_t seed = 9001;
    for (const char* scene : {"demo", "hilly", "hard", "slopes", "forest"}) {
        // The forest's tank rests tilted across its slope: it stays on that slope.
        const int reach_m = std::string(scene) == "slopes" ? 20 : std::string(scene) == "forest" ? 5 : 40;
        nlohmann::json spec = {
            {"scene", (assets / scene / "scene.json").string()},
            {"count", eval_count},
            {"seed", seed++},
            {"vary",
             {{"target_yaw_deg", {{"min", 0}, {"max", 360}}},
              {"target_offset_m", {{"min", 0}, {"max", reach_m}}},
              {"target_files", {(assets / "common" / "tank.obj").string(), (assets / "common" / "truck.obj").string()}},
              {"environment_keep_fraction", {{"min", 0.7}, {"max", 1.0}}},
              {"sensor_preset", {"ideal", "riegl-vux1uav", "livox-avia"}},
              // Within the shorter-ranged preset's reach (450 m at 300 m and 45 deg).
              {"altitude_m", {{"min", 200}, {"max", 300}}},
              {"alpha_deg", {{"min", 30}, {"max", 45}}},
              {"resolution", 128}}}};
        if (o.quick) spec["vary"]["views"] = 16;
        const fs::path dir = tmp / (std::string("eval_") + scene);
        const std::size_t failed =
            buildCorpus(writeSpec(tmp, std::string("eval_") + scene, spec), dir, o.threads, true);
        left_out += failed;
        // Every item left out (the forest's few --quick items can all find no room): no clouds of this scene.
        if (failed >= std::size_t(eval_count)) continue;
        const detect::CorpusListing l = detect::listCorpus(dir);
        const std::map<std::string, std::string> sensors = sensorOfItems(dir);
        for (std::size_t k = 0; k < l.ids.size(); ++k) {
            const std::string sensor = sensors.count(l.ids[k]) ? sensors.at(l.ids[k]) : "ideal";
            clouds.push_back(
                {std::string(scene) + " " + l.ids[k] + " " + sensor, io::readCloud(l.cloud(k)), sensor == "ideal"});
        }
    }
    for (const std::string_view preset : sim::sensorPresetNames()) {
        if (preset == "ideal") continue;
        for (const char* scene : {"demo", "hilly", "hard", "forest"}) {
            if (o.quick && std::string(scene) != "demo") continue;
            sim::GenerateOptions g;
            g.sensor = sim::sensorPreset(preset);
            g.threads = o.threads;
            if (o.quick) g.orbit.views = 16;
            std::fprintf(stderr, "bench detect: %s seen by %s\n", scene, std::string(preset).c_str());
            clouds.push_back({std::string(scene) + " " + std::string(preset),
                              sim::generateCloud(io::loadScene(assets / scene / "scene.json"), g), false});
        }
    }

    detect::BoostedOptions bo;
    bo.min_probability = 0.0;
    bo.max_candidates = 1000000;
    bo.threads = o.threads;
    const detect::BoostedDetector trained(bo, model);
    detect::ClusterOptions co;
    co.min_score = 0.0;
    co.max_candidates = 1000000;
    const detect::ClusterDetector baseline(co);
    std::vector<Outcome> t_out, b_out;
    std::ostringstream per;
    per << "| cloud | points | trained rank | baseline rank | trained detect s (min-max) | baseline detect s "
           "(min-max) |\n|---|---:|---:|---:|---:|---:|\n";
    auto spread = [](const Outcome& x) {
        return fmt("%.2f", x.seconds) + " (" + fmt("%.2f", x.seconds_min) + "-" + fmt("%.2f", x.seconds_max) + ")";
    };
    for (const Cloud& c : clouds) {
        t_out.push_back(evaluate(trained, c.cloud, o.repeats, c.name));
        b_out.push_back(evaluate(baseline, c.cloud, o.repeats, c.name));
        per << "| " << c.name << " | " << c.cloud.points.size() << " | "
            << (t_out.back().rank ? std::to_string(t_out.back().rank) : "not found") << " | "
            << (b_out.back().rank ? std::to_string(b_out.back().rank) : "not found") << " | " << spread(t_out.back())
            << " | " << spread(b_out.back()) << " |\n";
        std::fprintf(stderr, "bench detect: %s: trained rank %d, baseline rank %d\n", c.name.c_str(), t_out.back().rank,
                     b_out.back().rank);
    }
    const Summary ts = summarise(t_out), bs = summarise(b_out);
    if (!o.pr_csv.empty()) {
        if (o.pr_csv.has_parent_path()) fs::create_directories(o.pr_csv.parent_path());
        platform::writeFileAtomic(o.pr_csv, "detector,threshold,precision,recall,false_per_cloud\n" +
                                                prRows("trained", t_out) + prRows("baseline", b_out));
        std::fprintf(stderr, "bench detect: precision-recall curves in %s\n", o.pr_csv.c_str());
    }
    std::vector<Outcome> t_ideal, t_noisy, b_ideal, b_noisy;
    for (std::size_t k = 0; k < clouds.size(); ++k) {
        (clouds[k].ideal ? t_ideal : t_noisy).push_back(t_out[k]);
        (clouds[k].ideal ? b_ideal : b_noisy).push_back(b_out[k]);
    }
    std::ostringstream s;
    s << "Trained on " << report.items << " items (" << report.heldout_items << " held out for the calibration), "
      << report.segments << " segments, " << report.positives << " target segments, in " << fmt("%.1f", train_s)
      << " s (trees only; the clouds' segments and features before that). Evaluated on " << clouds.size() << " clouds"
      << ", each detected " << std::max(1, o.repeats) << " times by each detector (detect s: the median)"
      << (o.quick ? " (--quick: tiny corpora and clouds, a smoke run, not a measurement)" : "")
      << (left_out ? "; " + std::to_string(left_out) + " evaluation items were left out (no free place for the target)"
                   : std::string())
      << ".\n\n"
      << "| detector | clouds | target ranked 1st | in the top 3 | found at all | threshold for >= 90 % found | "
         "false candidates per cloud there | median detect s | slowest detect s "
         "|\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n"
      << summaryRow("trained (`--model`)", ts) << summaryRow("clustering baseline", bs)
      << summaryRow("trained, ideal sensor", summarise(t_ideal))
      << summaryRow("baseline, ideal sensor", summarise(b_ideal))
      << summaryRow("trained, sensor presets", summarise(t_noisy))
      << summaryRow("baseline, sensor presets", summarise(b_noisy)) << "\n"
      << per.str();
    return s.str();
}

std::string rankClouds(const TrainedBenchOptions& o) {
    detect::BoostedOptions bo;
    bo.model = o.model;
    bo.min_probability = 0.0;
    bo.max_candidates = 1000000;
    bo.threads = o.threads;
    const detect::BoostedDetector trained(bo);
    detect::ClusterOptions co;
    co.min_score = 0.0;
    co.max_candidates = 1000000;
    const detect::ClusterDetector baseline(co);
    std::ostringstream s;
    s << "| cloud | points | target points | ground sigma m | height threshold m | above terrain | segments | "
         "largest segment | target's segment (target points) | trained rank (score) | baseline rank |\n"
         "|---|---:|---:|---:|---:|---:|---:|---:|---|---|---:|\n";
    std::ostringstream why;
    if (o.explain > 0)
        why << "\n| cloud | rank | probability | points | target points | box m (l x w x h) | centre z m |\n"
               "|---|---:|---:|---:|---:|---|---:|\n";
    for (const fs::path& path : o.clouds) {
        const core::PointCloud c = io::readCloud(path);
        std::size_t target_points = 0;
        for (const core::CloudPoint& p : c.points) target_points += p.label == core::Role::Target;
        detect::BoostedStats st;
        const std::vector<detect::Detection> found = trained.detect(c, st);
        std::size_t largest = 0, best = 0, best_target = 0, rank = 0;
        const std::string name = path.string();
        for (std::size_t k = 0; k < found.size(); ++k) {
            largest = std::max(largest, found[k].points.size());
            std::size_t t = 0;
            for (const std::uint32_t i : found[k].points) t += c.points[i].label == core::Role::Target;
            if (t > best_target) best_target = t, best = k;
            const bool tp = 2 * t > found[k].points.size();
            if (tp && rank == 0) rank = k + 1;
            if (o.explain > 0 && (int(k) < o.explain || tp)) {
                const core::Candidate& a = found[k].candidate;
                why << "| " << name << " | " << k + 1 << " | " << fmt("%.3f", a.score) << " | "
                    << found[k].points.size() << " | " << t << " | " << fmt("%.1f", a.size_m.x) << " x "
                    << fmt("%.1f", a.size_m.y) << " x " << fmt("%.1f", a.size_m.z) << " | "
                    << fmt("%.1f", a.centre_world.z) << " |\n";
            }
        }
        const Outcome b_out = evaluate(baseline, c, 1, name);
        s << "| " << name << " | " << c.points.size() << " | " << target_points << " | "
          << fmt("%.3f", st.ground_sigma_m) << " | " << fmt("%.2f", st.min_height_m) << ", core " << st.core_points
          << " | " << st.above_points << " | " << st.segments << " | " << largest << " | "
          << (best_target ? std::to_string(found[best].points.size()) + " (" + std::to_string(best_target) + ")"
                          : std::string("none"))
          << " | "
          << (rank ? std::to_string(rank) + " (" + fmt("%.3f", found[rank - 1].candidate.score) + ")"
                   : std::string("not found"))
          << " | " << (b_out.rank ? std::to_string(b_out.rank) : std::string("not found")) << " |\n";
        std::fprintf(stderr, "bench detect: %s done\n", path.string().c_str());
    }
    return s.str() + why.str();
}

}  // namespace bench
