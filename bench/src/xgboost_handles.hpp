// bench/src/xgboost_handles.hpp: XGBoost's C handles owned by objects, for the bench's
// learned ground rows (ground_isprs_learned.cpp, ground_isprs_selector_fits.cpp). A failed
// call is one core::Error naming the bench step, the call and XGBoost's own message.
#pragma once

#include <core/error.hpp>

#include <xgboost/c_api.h>

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace bench {

/// Throws core::Error("CONTEXT: XGBoost: WHAT: <XGBoost's last error>").
[[noreturn]] inline void xgboostFail(const char* context, const char* what) {
    throw core::Error(std::string(context) + ": XGBoost: " + what + ": " + XGBGetLastError());
}

/// A dense matrix of rows.size() / columns rows (NaN: missing), freed with the object.
struct XgbMatrix {
    DMatrixHandle h = nullptr;
    XgbMatrix(const std::vector<float>& rows, std::size_t columns, const char* context) {
        if (XGDMatrixCreateFromMat(rows.data(), bst_ulong(rows.size() / columns), bst_ulong(columns),
                                   std::numeric_limits<float>::quiet_NaN(), &h) != 0)
            xgboostFail(context, "matrix");
    }
    ~XgbMatrix() { XGDMatrixFree(h); }
    XgbMatrix(const XgbMatrix&) = delete;
    XgbMatrix& operator=(const XgbMatrix&) = delete;
};

/// A booster handle, freed with the object (created by the caller).
struct XgbBooster {
    BoosterHandle h = nullptr;
    XgbBooster() = default;
    ~XgbBooster() { XGBoosterFree(h); }
    XgbBooster(const XgbBooster&) = delete;
    XgbBooster& operator=(const XgbBooster&) = delete;
};

}  // namespace bench
