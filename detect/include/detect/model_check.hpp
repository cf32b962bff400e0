// detect/model_check.hpp: a strict check of XGBoost's model bytes (its UBJSON form)
// before XGBoost parses them. XGBoost trusts its model: a child index out of range, a
// split on a feature the data lacks, categorical data or an output group out of range
// make it read out of bounds or abort, and a child that leads back up the tree makes its
// prediction loop forever. The model file's SHA-256 is stored in the same file, so it
// catches accidents only. This checker accepts what `ladarvr train` writes (a gbtree of
// binary:logistic trees with numeric splits, one output group) and refuses the rest.
//
// It has its own small UBJSON parser (big-endian; markers Z T F i U I l L d D C S H [ ] { }
// and the optimized `$type` / `#count` forms): nesting is capped, every count and length
// is checked against the bytes left before anything is kept, duplicate keys, unknown
// markers, the no-op N (XGBoost writes none, and a reader that takes it for a value would
// see other elements than this one) and bytes after the end are refused. Then every
// field is checked against the form XGBoost 3 writes: which keys, which UBJSON types,
// which values; each tree's per-node arrays have num_nodes values, its children are in
// range and form a tree from the root (each node reached once, depth capped), its splits
// name features below the feature count, no split is categorical.
//
// Depends on core and the standard library only (the fuzz build compiles it alone).
#pragma once
#include <cstddef>
#include <string>
#include <string_view>

namespace detect {

inline constexpr int kMaxModelNesting = 64;                           // UBJSON containers inside containers
inline constexpr int kMaxTreeDepth = 64;                              // edges from a tree's root to a leaf
inline constexpr std::size_t kMaxModelValues = std::size_t(1) << 19;  // parsed values (an optimized array is one)

/// Checks XGBoost's model bytes `ubjson` against what `ladarvr train` writes, for a model
/// of `features` input columns. Throws core::Error(where + ": " + what), one line naming
/// the byte, the field or the tree and node at fault and what is allowed, e.g.
/// "tree 12 node 5: left child 99: allowed -1 (a leaf) or 1..14".
void checkXgboostModel(std::string_view ubjson, std::size_t features, const std::string& where);

}  // namespace detect
