// fuzz/fuzz_detect_model.cpp: libFuzzer target for the detector model's XGBoost bytes:
// detect::checkXgboostModel (detect/src/model_check.cpp, compiled here without the rest
// of detect), then, for bytes it passes, XGBoost itself (Debian's libxgboost) loading them
// as BoostedModel::read does and predicting one row of NaN (every feature missing) and
// one of zeros. The input is the UBJSON after the model file's header (seeds: fuzz/seeds/model,
// from fuzz/make_seeds.py). The contract: no crash, no hang, nothing out of bounds, in the
// checker or in XGBoost on what the checker passes; a refusal is one printable ASCII line;
// a model the checker passes has the feature count it checked and gives one margin a row.
#include <detect/model_check.hpp>

#include <core/error.hpp>
#include "check_message.hpp"

#include <xgboost/c_api.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string_view>
#include <vector>

namespace {

constexpr std::size_t kFeatures = 52;  // the shipped model's features (the second set), the seeds' num_feature
constexpr std::size_t kMaxBytes = std::size_t(1) << 20;  // the seeds are at most 155 KB

bool verbose() {
    static const bool v = std::getenv("LADARVR_FUZZ_VERBOSE") != nullptr;
    return v;
}

// XGBoost's refusal of bytes the checker passed: allowed (its own checks may be stricter),
// shown with LADARVR_FUZZ_VERBOSE.
void xgboostRefused() {
    if (verbose()) std::fprintf(stderr, "XGBoost refused: %.300s\n", XGBGetLastError());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > kMaxBytes) return -1;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    try {
        detect::checkXgboostModel(bytes, kFeatures, "detect: --model fuzz.ldm");
    } catch (const core::Error& e) {
        fuzz::checkMessage(e.what(), true);
        if (verbose()) std::fprintf(stderr, "refused: %s\n", e.what());
        return 0;
    }
    BoosterHandle booster = nullptr;
    if (XGBoosterCreate(nullptr, 0, &booster) != 0) std::abort();
    if (XGBoosterSetParam(booster, "nthread", "1") != 0) std::abort();
    if (XGBoosterLoadModelFromBuffer(booster, data, bst_ulong(size)) != 0) {
        xgboostRefused();
        XGBoosterFree(booster);
        return 0;
    }
    bst_ulong columns = 0;
    if (XGBoosterGetNumFeature(booster, &columns) != 0 || columns != kFeatures) {
        std::fprintf(stderr, "the checker passed a model of %llu features, not %zu\n",
                     static_cast<unsigned long long>(columns), kFeatures);
        std::abort();
    }
    std::vector<float> rows(2 * kFeatures, 0.0f);
    for (std::size_t k = 0; k < kFeatures; ++k) rows[k] = std::numeric_limits<float>::quiet_NaN();
    DMatrixHandle matrix = nullptr;
    if (XGDMatrixCreateFromMat(rows.data(), 2, bst_ulong(kFeatures), std::numeric_limits<float>::quiet_NaN(),
                               &matrix) != 0)
        std::abort();
    bst_ulong length = 0;
    const float* margins = nullptr;
    if (XGBoosterPredict(booster, matrix, 1 /* margin */, 0, 0, &length, &margins) != 0)
        xgboostRefused();
    else if (length != 2) {
        std::fprintf(stderr, "XGBoost returned %llu margins for 2 rows\n", static_cast<unsigned long long>(length));
        std::abort();
    }
    XGDMatrixFree(matrix);
    XGBoosterFree(booster);
    return 0;
}
