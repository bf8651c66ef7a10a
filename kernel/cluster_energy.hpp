// The cache of relaxed Monte Carlo cluster energies by canonical shape (shape_key.hpp); the
// relaxation itself is relax_policy.hpp's.
#pragma once

#include "relax_policy.hpp"
#include "shape_key.hpp"

#include <cstdint>
#include <string>
#include <unordered_map>

namespace pyfrustrate {

// Relaxed energies by shape key, cleared whole when it would hold more than `limit` key
// entries (8 bytes each): results never depend on it, only speed does.
struct CacheCounters {
    std::int64_t hits = 0, misses = 0, clears = 0;
};

class ClusterEnergyCache {
   public:
    std::size_t limit = std::size_t(1) << 24;

    // The cached energy of `key`, or compute() stored under it.
    template <class Compute>
    double get(const ShapeKey& key, Compute&& compute, CacheCounters& counters) {
        const auto it = map_.find(key);
        if (it != map_.end()) {
            ++counters.hits;
            return it->second;
        }
        ++counters.misses;
        const double e = compute();
        if (entries_ + key.size() > limit) {
            clear();
            ++counters.clears;
        }
        entries_ += key.size();
        map_.emplace(key, e);
        return e;
    }
    // The cached energy of `key` without counting a hit or a miss; nullptr if it is not cached.
    const double* peek(const ShapeKey& key) const {
        const auto it = map_.find(key);
        return it == map_.end() ? nullptr : &it->second;
    }
    std::size_t size() const { return map_.size(); }
    void clear() { map_.clear(); entries_ = 0; }

   private:
    std::unordered_map<ShapeKey, double, ShapeKeyHash> map_;
    std::size_t entries_ = 0;
};

}  // namespace pyfrustrate
