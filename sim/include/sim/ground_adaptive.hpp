// sim/ground_adaptive.hpp: SMRF's parameters chosen per input from the data itself. A
// first SMRF fit with `ladarvr ground`'s defaults gives the survey's traits (its terrain's
// slope and roughness, its share of objects, its density); a rule with fixed constants
// turns them into the slope, window, threshold and scalar of the fit that labels the
// points. Nothing is given per input: the rule and its constants are the same for every
// survey.
#pragma once
#include <core/point_cloud.hpp>
#include <sim/ground.hpp>

#include <span>
#include <string>
#include <vector>

namespace sim {

/// What the adaptive choice measures of a survey (from SMRF's fit with the options given).
struct SurveyTraits {
    double points_per_m2 = 0;  // points over the area of the cells that hold one
    double empty_share = 0;    // share of the raster's cells without a point
    double slope_p50 = 0;      // the fitted terrain's slope (rise over run) over the observed
    double slope_p90 = 0;      // cells: median and 90th percentile
    double steep_share = 0;    // share of observed cells whose terrain slope is over 0.5
    double relief_m = 0;       // the terrain's 95th minus 5th percentile height
    double rough_m = 0;        // median |terrain - mean of the terrain 2 cells around| (curvature)
    double object_share = 0;   // share of the points not ground
    double high_share = 0;     // share of the points more than 2.5 m above the terrain
    double edge_share = 0;     // share of observed ground cells next to an object cell
};

/// The traits' names, in the order traitValues gives them.
const std::vector<std::string>& surveyTraitNames();
/// The traits as one row, in surveyTraitNames()'s order.
std::vector<double> traitValues(const SurveyTraits& t);

/// Measures `points` with SMRF options `o` (validate(o) passed). Throws core::Error as
/// SMRF's fit does (a raster over o.max_cells).
SurveyTraits measureSurvey(std::span<const core::CloudPoint> points, const SmrfOptions& o);

}  // namespace sim
