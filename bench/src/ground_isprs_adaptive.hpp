// bench/src/ground_isprs_adaptive.hpp: SMRF's parameters chosen per input on the ISPRS
// samples: the oracle (each sample's or tile's best over a grid of slope, window,
// threshold and scalar), and a rule on the survey's traits fitted leave-one-site-out.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace core {
struct CloudPoint;
}

namespace bench {

/// Reference x found (ground / object) over some points, and the scores papers give.
struct Confusion {
    double gg = 0, go = 0, og = 0, oo = 0;
    void add(bool truth, bool found) {
        if (truth)
            (found ? gg : go) += 1;
        else
            (found ? og : oo) += 1;
    }
    void add(const Confusion& c) { gg += c.gg, go += c.go, og += c.og, oo += c.oo; }
    double wrong() const { return go + og; }
    double points() const { return gg + go + og + oo; }
};

/// Type I, type II, total error and Cohen's kappa, percent.
struct Counts {
    double type1 = 0, type2 = 0, total = 0, kappa = 0;
};
Counts countsOf(const Confusion& c);

/// The square tiles of `tile_m` a sample's points fall in, numbered from its lowest corner.
struct Tiles {
    std::vector<std::uint32_t> of;                  // per point
    std::vector<std::vector<std::size_t>> members;  // per tile, its points
};
Tiles tilesOf(const std::vector<core::CloudPoint>& points, double tile_m);

/// CSF's published total error (Zhang et al. 2016) for an ISPRS sample ("samp11"), percent;
/// -1 for another name.
double csfPublishedTotal(const std::string& sample);

/// One sample as the adaptive measurements see it.
struct AdaptiveSample {
    std::string name;
    const std::vector<core::CloudPoint>* points = nullptr;
    const std::vector<std::uint8_t>* truth = nullptr;  // 1 = bare earth
};

/// Scores every sample over the grid of SMRF options (`ladarvr ground`'s defaults otherwise)
/// and writes one CSV line per sample and grid point to `csv`: name, the options, type I,
/// type II, total, kappa. Then prints each sample's best (the oracle, which sees the
/// reference labels) and the selection rule's figures leave-one-site-out (each sample's
/// options chosen by a rule fitted on the other sites' samples), and the same per square
/// tile of 100 and 50 m (each tile's points labelled by the whole sample's fit with the
/// options chosen for the tile from its own traits). Throws core::Error.
void writeAdaptiveGrid(const std::vector<AdaptiveSample>& samples, const std::string& csv);

/// A choice of SMRF options per survey from its traits (sim::SurveyTraits): the base set,
/// or the alternative set where the trait lies above (or at most at) the threshold.
struct SelectionRule {
    int trait = -1;  // index into sim::surveyTraitNames(); -1: always the base set
    double threshold = 0;
    bool above = true;                      // the alternative where trait > threshold (else <=)
    std::size_t base = 0, alternative = 0;  // indices of option sets
    /// The option set for a survey with these traits.
    std::size_t choose(const std::vector<double>& traits) const;
};

/// The rule that minimises the mean error over the `train` samples: `errors[k][g]` is sample
/// k's error under option set g, `traits[k]` its traits. Each trait and each threshold
/// midway between two training values is tried, each side, with the alternative set best
/// on the samples it picks (at least two of them); the base set is kept where no rule does
/// better than it alone.
SelectionRule fitSelectionRule(const std::vector<std::vector<double>>& errors,
                               const std::vector<std::vector<double>>& traits, const std::vector<std::size_t>& train,
                               std::size_t base);

/// Writes each sample's survey traits (sim::measureSurvey with `ladarvr ground`'s SMRF
/// defaults) to `csv`: name, then one column per trait. Throws core::Error.
void writeAdaptiveTraits(const std::vector<AdaptiveSample>& samples, const std::string& csv);

}  // namespace bench
