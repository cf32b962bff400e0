// study/instruments.hpp: the standard questionnaires a study asks in the headset, their
// items and their scoring, and the layout of questionnaires.csv. Pure functions: no file
// or OS access, so the session that asks and the report that scores share one definition.
//
// - The Simulator Sickness Questionnaire (Kennedy, Lane, Berbaum and Lilienthal 1993,
//   "Simulator Sickness Questionnaire: an enhanced method for quantifying simulator
//   sickness", Int. J. Aviation Psychology 3(3)): 16 symptoms rated 0 none, 1 slight,
//   2 moderate, 3 severe; three overlapping clusters of seven items, each raw sum weighted
//   (nausea 9.54, oculomotor 7.58, disorientation 13.92) and the total the sum of the
//   three raw sums times 3.74.
// - NASA-TLX, raw (Hart 2006, "NASA-Task Load Index (NASA-TLX); 20 years later"): six
//   subscales rated 0 to 100 in steps of 5, the raw score their mean (no pairwise weights).
// - Likert items: a statement rated 1 to N (N from 2 to 11).
//
// questionnaires.csv has one row per answered item, in the order answered:
//   participant,condition,instrument,occasion,item,response,time_s
// instrument is `ssq`, `tlx`, `likert` or `text`; occasion is `pre` (before the session's
// first trial), `post` (after its last), or `after_condition`; condition is the condition
// just run (empty for `pre`); item is the item's id below (a Likert or text item's own id);
// response is the rating as a whole number, or the text (CSV-quoted); time_s counts seconds
// from the start of the session.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string_view>

namespace study {

/// One item of an instrument: a stable id (the `item` column) and the text shown.
struct InstrumentItem {
    std::string_view id;
    std::string_view text;
};

/// SSQ symptom clusters an item belongs to (bit flags).
enum SsqCluster : unsigned { kSsqNausea = 1u, kSsqOculomotor = 2u, kSsqDisorientation = 4u };

struct SsqItem {
    InstrumentItem item;
    unsigned clusters = 0;  // SsqCluster bits
};

inline constexpr int kSsqItemCount = 16;
inline constexpr int kSsqMaxRating = 3;
inline constexpr int kTlxItemCount = 6;
inline constexpr int kTlxMaxRating = 100;
inline constexpr int kTlxStep = 5;

/// The 16 SSQ symptoms in Kennedy et al.'s order, with their clusters.
std::span<const SsqItem> ssqItems();
/// The six NASA-TLX subscales in Hart's order (mental, physical, temporal, performance,
/// effort, frustration); performance runs from good (0) to poor (100) as on the paper form.
std::span<const InstrumentItem> tlxItems();

struct SsqScores {
    double nausea = 0;
    double oculomotor = 0;
    double disorientation = 0;
    double total = 0;
};

/// Scores 16 ratings given in ssqItems() order. Throws core::Error naming the item when a
/// rating is outside 0..3 or the count is not 16.
SsqScores scoreSsq(std::span<const int> ratings);
/// The raw TLX: the mean of six ratings given in tlxItems() order. Throws core::Error naming
/// the subscale when a rating is outside 0..100 or not a multiple of 5.
double scoreTlxRaw(std::span<const int> ratings);

/// The index of an SSQ or TLX item id, or nullopt.
std::optional<int> ssqItemIndex(std::string_view id);
std::optional<int> tlxItemIndex(std::string_view id);

}  // namespace study
