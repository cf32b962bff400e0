// study/src/instruments.cpp: the SSQ and NASA-TLX items and their scoring
// (study/instruments.hpp says where each rule comes from).
#include <study/instruments.hpp>

#include <core/error.hpp>

#include <string>

namespace study {
namespace {

constexpr unsigned N = kSsqNausea, O = kSsqOculomotor, D = kSsqDisorientation;

constexpr std::array<SsqItem, kSsqItemCount> kSsq{{
    {{"general_discomfort", "General discomfort"}, N | O},
    {{"fatigue", "Fatigue"}, O},
    {{"headache", "Headache"}, O},
    {{"eyestrain", "Eye strain"}, O},
    {{"difficulty_focusing", "Difficulty focusing"}, O | D},
    {{"salivation_increasing", "Salivation increasing"}, N},
    {{"sweating", "Sweating"}, N},
    {{"nausea", "Nausea"}, N | D},
    {{"difficulty_concentrating", "Difficulty concentrating"}, N | O},
    {{"fullness_of_head", "Fullness of the head"}, D},
    {{"blurred_vision", "Blurred vision"}, O | D},
    {{"dizziness_eyes_open", "Dizziness with eyes open"}, D},
    {{"dizziness_eyes_closed", "Dizziness with eyes closed"}, D},
    {{"vertigo", "Vertigo"}, D},
    {{"stomach_awareness", "Stomach awareness"}, N},
    {{"burping", "Burping"}, N},
}};

constexpr std::array<InstrumentItem, kTlxItemCount> kTlx{{
    {"mental", "Mental demand: how mentally demanding was the task?"},
    {"physical", "Physical demand: how physically demanding was the task?"},
    {"temporal", "Temporal demand: how hurried or rushed was the pace of the task?"},
    {"performance",
     "Performance: how successful were you in accomplishing what you were asked to do? (0 perfect, 100 failure)"},
    {"effort", "Effort: how hard did you have to work to accomplish your level of performance?"},
    {"frustration", "Frustration: how insecure, discouraged, irritated, stressed and annoyed were you?"},
}};

}  // namespace

std::span<const SsqItem> ssqItems() { return kSsq; }
std::span<const InstrumentItem> tlxItems() { return kTlx; }

SsqScores scoreSsq(std::span<const int> ratings) {
    if (ratings.size() != kSsq.size())
        throw core::Error("ssq: " + std::to_string(ratings.size()) + " ratings; allowed: exactly 16, one per symptom");
    int n = 0, o = 0, d = 0;
    for (std::size_t i = 0; i < kSsq.size(); ++i) {
        const int r = ratings[i];
        if (r < 0 || r > kSsqMaxRating)
            throw core::Error("ssq: " + std::string(kSsq[i].item.id) + " rated " + std::to_string(r) +
                              "; allowed: 0 (none), 1 (slight), 2 (moderate) or 3 (severe)");
        if (kSsq[i].clusters & kSsqNausea) n += r;
        if (kSsq[i].clusters & kSsqOculomotor) o += r;
        if (kSsq[i].clusters & kSsqDisorientation) d += r;
    }
    SsqScores s;
    s.nausea = n * 9.54;
    s.oculomotor = o * 7.58;
    s.disorientation = d * 13.92;
    s.total = (n + o + d) * 3.74;
    return s;
}

double scoreTlxRaw(std::span<const int> ratings) {
    if (ratings.size() != kTlx.size())
        throw core::Error("tlx: " + std::to_string(ratings.size()) + " ratings; allowed: exactly 6, one per subscale");
    int sum = 0;
    for (std::size_t i = 0; i < kTlx.size(); ++i) {
        const int r = ratings[i];
        if (r < 0 || r > kTlxMaxRating || r % kTlxStep != 0)
            throw core::Error("tlx: " + std::string(kTlx[i].id) + " rated " + std::to_string(r) +
                              "; allowed: 0 to 100 in steps of 5");
        sum += r;
    }
    return double(sum) / double(kTlx.size());
}

std::optional<int> ssqItemIndex(std::string_view id) {
    for (std::size_t i = 0; i < kSsq.size(); ++i)
        if (kSsq[i].item.id == id) return int(i);
    return std::nullopt;
}

std::optional<int> tlxItemIndex(std::string_view id) {
    for (std::size_t i = 0; i < kTlx.size(); ++i)
        if (kTlx[i].id == id) return int(i);
    return std::nullopt;
}

}  // namespace study
