// The relaxed deformation energy of one Monte Carlo cluster, and the cache of those energies by
// canonical shape (shape_key.hpp).
#pragma once

#include "relax.hpp"
#include "shape_key.hpp"

#include <cstdint>
#include <string>
#include <unordered_map>

namespace pyfrustrate {

enum class RelaxMethod { Linear = 0, Lbfgs = 1, Newton = 2 };

struct ClusterRelaxOptions {
    RelaxMethod method = RelaxMethod::Linear;
    MinimizeOptions minimize;  // L-BFGS: absolute gradient tolerance, evaluation cap, step scale
    bool warm_start = true;    // L-BFGS starts from the linear solution (else the bulk reference)
    bool own_ldl = false;      // Newton: the kernel's own LDL^T on CHOLMOD's ordering (cholesky.hpp)
};

struct RelaxCounters {
    std::int64_t minimisations = 0;  // clusters relaxed
    std::int64_t evaluations = 0;    // energy+gradient evaluations (1 per linear solve)
    std::int64_t fallbacks = 0;      // linear solves refused (floppy topology), done by L-BFGS
    std::int64_t unconverged = 0;    // L-BFGS runs stopped short of the tolerance
    std::int64_t factorizations = 0; // Newton: numeric factorisations (exact Hessians and reference stiffness)
    std::int64_t warm_starts = 0;    // Newton runs started from a neighbouring relaxed state
    std::int64_t warm_restarts = 0;  // warm starts outside the minimum's basin, redone from the linear solution
};

// Minimum deformation energy of `topology` (main text Eq. 7, inner minimisation): the linear
// solve (exact as eps -> 0; a floppy topology falls back to L-BFGS from the bulk reference),
// or L-BFGS started from the linear solution (warm start) or from the bulk reference.
//
// Newton only: `start` (optional) is the displacement to start from instead of the linear
// solution, a warm start (exact Hessian from the first step); `displacement` (optional) receives
// the relaxed displacement.
template <class Model>
double relaxed_cluster_energy(const Model& model, const Topology& topology, const ClusterRelaxOptions& options,
                              RelaxCounters& counters, const Vector* start = nullptr, Vector* displacement = nullptr) {
    ++counters.minimisations;
    if (displacement) displacement->resize(0);
    if (options.method == RelaxMethod::Newton) {
        try {
            StiffnessCache stiffness(topology, options.own_ldl);
            MinimizeResult r;
            if (start) {
                // A warm start whose exact Hessian stays indefinite is not in the minimum's basin
                // (a moved particle strained across its neighbours): Newton from the linear
                // solution instead, which the measured dense runs never hand over, where L-BFGS
                // from the warm state took a tenth of the run in 0.6 % of the relaxations.
                MinimizeOptions warm = options.minimize;
                warm.newton_exact_from_start = true;
                warm.newton_handover = true;
                ++counters.warm_starts;
                r = newton_from(model, topology, *start, warm, stiffness);
                counters.evaluations += r.iterations;
                counters.factorizations += r.factorizations;
                if (r.handed_over) ++counters.warm_restarts;
            }
            if (!start || r.handed_over) {
                r = relax_newton(model, topology, options.minimize, &stiffness);
                counters.evaluations += r.iterations;
                counters.factorizations += r.factorizations;
            }
            counters.factorizations += stiffness.reference_factorizations();
            if (!r.converged) ++counters.unconverged;
            if (r.energy >= 0) {
                if (displacement) *displacement = r.displacement;
                return r.energy;
            }
        } catch (const std::runtime_error&) {
            ++counters.fallbacks;  // floppy topology: no factorisation, L-BFGS below
        }
    }
    Vector x0;
    if (options.method == RelaxMethod::Linear || options.warm_start) {
        try {
            MinimizeResult linear = relax_linear(model, topology);
            ++counters.evaluations;
            if (options.method == RelaxMethod::Linear) return linear.energy;
            x0 = std::move(linear.x);
        } catch (const std::runtime_error&) {
            ++counters.fallbacks;
        }
    }
    if (x0.size() == 0) x0 = topology.reference_state();
    const MinimizeResult r = relax_lbfgs(model, topology, x0, options.minimize);
    counters.evaluations += r.iterations;
    if (displacement && r.energy >= 0) *displacement = r.displacement;
    if (!r.converged) ++counters.unconverged;
    // Every term is non-negative near the reference: a negative energy means that L-BFGS left
    // the physical basin (k_area < 0), and the Monte Carlo must not go on with it.
    if (!(r.energy >= 0))
        throw std::runtime_error("L-BFGS left the physical minimum of a cluster (energy " + std::to_string(r.energy) +
                                 " < 0); use method='linear' or a smaller tol");
    return r.energy;
}

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
    std::size_t size() const { return map_.size(); }
    void clear() { map_.clear(); entries_ = 0; }

   private:
    std::unordered_map<ShapeKey, double, ShapeKeyHash> map_;
    std::size_t entries_ = 0;
};

}  // namespace pyfrustrate
