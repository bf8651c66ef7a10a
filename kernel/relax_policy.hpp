// The one relaxation policy (issue 32, item 2): which minimiser runs (linear, Newton, L-BFGS),
// from where (the method's own start, a warm start, the parent cluster's state and factor),
// what happens when it fails (a warm start outside the basin restarts from the linear
// solution; a floppy topology or an unphysical Newton result goes to L-BFGS where the caller
// tolerates it), and the handover between them. pf.relax and the Monte Carlo both call
// relax_by_policy; the minimisers themselves live in relax.hpp and parent_factor.hpp.
#pragma once

#include "parent_factor.hpp"
#include "relax.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

namespace pyfrustrate {

enum class RelaxMethod { Linear = 0, Lbfgs = 1, Newton = 2, Auto = 3 };

// What a relaxation is asked to do.
struct RelaxRequest {
    RelaxMethod method = RelaxMethod::Auto;
    MinimizeOptions minimize;  // gradient tolerance (absolute), evaluation cap, L-BFGS memory, step scale
    // A displacement to start from (a warm start): Newton takes exact steps from it, L-BFGS
    // starts there. nullptr: Newton from the linear solution, L-BFGS as lbfgs_from_linear says.
    const Vector* start = nullptr;
    // L-BFGS without a start: from the linear solution (else the bulk reference); Auto then
    // means L-BFGS.
    bool lbfgs_from_linear = false;
    // Newton: the relaxed cluster this one differs from by a few particles (parent_factor.hpp).
    const RelaxedCluster* parent = nullptr;
    bool keep_factor = false;        // Newton: hand back this cluster's factor for its own children
    bool own_ldl = false;            // Newton: the kernel's own LDL^T on CHOLMOD's ordering (cholesky.hpp)
    // The Monte Carlo's tolerance: a floppy topology (its stiffness cannot be factorised) or a
    // Newton result below zero energy is redone by L-BFGS instead of raising; an L-BFGS result
    // below zero raises (it left the physical basin).
    bool fall_back_to_lbfgs = false;
    int rigid_pieces = 1;            // Auto: pieces joined by no side need L-BFGS (no pins for them)
};

struct RelaxCounters {
    std::int64_t minimisations = 0;  // clusters relaxed
    std::int64_t evaluations = 0;    // energy+gradient evaluations (1 per linear solve)
    std::int64_t fallbacks = 0;      // linear solves refused (floppy topology), done by L-BFGS
    std::int64_t unconverged = 0;    // L-BFGS runs stopped short of the tolerance
    std::int64_t factorizations = 0; // Newton: numeric factorisations (exact Hessians and reference stiffness)
    std::int64_t warm_starts = 0;    // Newton runs started from a neighbouring relaxed state
    std::int64_t warm_restarts = 0;  // warm starts outside the minimum's basin, redone from the linear solution
    std::int64_t parent_factor = 0;  // Newton runs on the parent's modified factor (parent_factor.hpp)
    std::int64_t parent_fresh = 0;   // of the runs given a parent, those made fresh instead
    std::int64_t parent_chord_steps = 0;        // chord steps of the runs on the parent's factor
    std::int64_t parent_refactorizations = 0;   // exact Hessians factorised anew along them
};

// What a relaxation hands back besides the minimiser's result.
struct RelaxExtras {
    std::shared_ptr<RelaxedCluster> factor;  // keep_factor: this cluster, ready for its children
    ParentRelaxStats parent;                 // a parent was given: how it served
    RelaxMethod method = RelaxMethod::Auto;  // the method that ran (Auto resolved)
};

// How many rigidly joined pieces a finite topology's particles form: particles are joined when
// they share a side, which in a topology of sites is when they are edge neighbours on the tiling
// (topology.hpp); a triangle touching another at one vertex only is a hinge, free to turn.
// Periodic cells count as one piece (their builders check connectivity).
inline int rigid_pieces(const Topology& t) {
    if (t.periodicity != Periodicity::None) return 1;
    const int np = t.n_particles();
    const SiteLookup particle_at(t.sites, t.tiling().sublattices);
    std::vector<int> root(np);
    for (int p = 0; p < np; ++p) root[p] = p;
    auto find = [&](int p) {
        while (root[p] != p) p = root[p] = root[root[p]];
        return p;
    };
    for (int p = 0; p < np; ++p)
        for (int d = 0; d < t.tiling().neighbours; ++d) {
            const int q = particle_at(neighbour_of(t.tiling(), t.sites[p], d));
            if (q >= 0) root[find(p)] = find(q);
        }
    int pieces = 0;
    for (int p = 0; p < np; ++p) pieces += find(p) == p;
    return pieces;
}

inline RelaxMethod resolved_method(const RelaxRequest& request) {
    if (request.method != RelaxMethod::Auto) return request.method;
    // The linear and Newton solves pin one rigid motion per topology: several pieces keep the
    // others' free, and the stiffness is singular. L-BFGS needs no pins, and takes a given start.
    return request.start || request.lbfgs_from_linear || request.rigid_pieces > 1 ? RelaxMethod::Lbfgs
                                                                                    : RelaxMethod::Newton;
}

template <class Model>
MinimizeResult relax_by_policy(const Model& model, const Topology& topology, const RelaxRequest& request,
                               RelaxCounters& counters, StiffnessCache* cache = nullptr, RelaxExtras* extras = nullptr) {
    RelaxExtras local_extras;
    RelaxExtras& out = extras ? *extras : local_extras;
    out.method = resolved_method(request);
    ++counters.minimisations;
    const bool tolerant = request.fall_back_to_lbfgs;
    if (out.method == RelaxMethod::Newton) {
        std::unique_ptr<StiffnessCache> own;
        if (!cache) own = std::make_unique<StiffnessCache>(topology, request.own_ldl);
        StiffnessCache& stiffness = cache ? *cache : *own;
        const int references_before = stiffness.reference_factorizations();
        try {
            MinimizeResult r;
            bool done = false;
            if (request.parent) {
                // The parent's factor, modified; made fresh (below) where it cannot serve.
                Vector start;
                std::shared_ptr<RelaxedCluster> child = modified_cluster(
                    model, topology, *request.parent, request.minimize.gradient_tolerance, start, out.parent.fresh_reason);
                if (!child && out.parent.fresh_reason == kNotPositiveDefinite)
                    child = modified_cluster(model, topology, *request.parent, request.minimize.gradient_tolerance, start,
                                             out.parent.fresh_reason, /*absolute_blocks=*/true);
                if (child) {
                    r = chord_relax(model, child, std::move(start), request.minimize, out.parent);
                    counters.evaluations += r.iterations;
                    counters.factorizations += r.factorizations;
                    // Exact only where the full gradient criterion holds: a chord run stopped
                    // short (round-off floor, evaluation cap) is redone below.
                    done = !r.handed_over && r.converged;
                    if (done) {
                        out.parent.from_parent = true;
                        ++counters.parent_factor;
                        counters.parent_chord_steps += out.parent.chord_steps;
                        counters.parent_refactorizations += out.parent.refactorizations;
#ifndef NDEBUG
                        // Debug builds: every 16th relaxation from a parent against a fresh one.
                        static std::atomic<int> checked{0};
                        if (r.converged && checked++ % 16 == 0) {
                            StiffnessCache fresh_cache(topology);
                            const MinimizeResult fresh = relax_newton(model, topology, request.minimize, &fresh_cache);
                            if (fresh.converged && std::abs(fresh.energy - r.energy) > 1e-6 * std::abs(fresh.energy) + 1e-300)
                                throw std::logic_error("relaxation from the parent's factor: energy " + std::to_string(r.energy) +
                                                       " against " + std::to_string(fresh.energy) + " relaxed fresh");
                        }
#endif
                        child->displacement = r.displacement;
                        if (request.keep_factor) out.factor = std::move(child);
                    } else {
                        out.parent.fresh_reason = r.status;
                    }
                }
                if (!done) ++counters.parent_fresh;
            }
            if (!done && request.start) {
                // A warm start whose exact Hessian stays indefinite is not in the minimum's basin
                // (a moved particle strained across its neighbours): Newton from the linear
                // solution instead, which the measured dense runs never hand over, where L-BFGS
                // from the warm state took a tenth of the run in 0.6 % of the relaxations.
                MinimizeOptions warm = request.minimize;
                warm.newton_exact_from_start = true;
                warm.newton_handover = true;
                ++counters.warm_starts;
                r = newton_from(model, topology, *request.start, warm, stiffness);
                counters.evaluations += r.iterations;
                counters.factorizations += r.factorizations;
                if (r.handed_over) ++counters.warm_restarts;
                done = !r.handed_over;
            }
            if (!done) {
                r = relax_newton(model, topology, request.minimize, &stiffness);
                counters.evaluations += r.iterations;
                counters.factorizations += r.factorizations;
            }
            counters.factorizations += stiffness.reference_factorizations() - references_before;
            if (!r.converged) ++counters.unconverged;
            if (r.energy >= 0 || !tolerant) {
                if (request.keep_factor && !out.factor && r.converged)
                    out.factor = factorised_cluster(model, topology, r.displacement, r.displacement);
                return r;
            }
        } catch (const std::runtime_error&) {
            if (!tolerant) throw;
            ++counters.fallbacks;  // floppy topology: no factorisation, L-BFGS below
        }
        out.method = RelaxMethod::Lbfgs;
    }
    Vector x0;
    if (request.start && out.method == RelaxMethod::Lbfgs) {
        x0 = state_of(topology, *request.start);
    } else if (out.method == RelaxMethod::Linear || request.lbfgs_from_linear) {
        try {
            MinimizeResult linear = relax_linear(model, topology, out.method == RelaxMethod::Linear ? cache : nullptr);
            ++counters.evaluations;
            if (out.method == RelaxMethod::Linear) return linear;
            x0 = std::move(linear.x);
        } catch (const std::runtime_error&) {
            if (!tolerant) throw;
            ++counters.fallbacks;
            out.method = RelaxMethod::Lbfgs;
        }
    }
    if (x0.size() == 0) x0 = topology.reference_state();
    MinimizeResult r = relax_lbfgs(model, topology, x0, request.minimize, tolerant ? nullptr : cache);
    counters.evaluations += r.iterations;
    if (!r.converged) ++counters.unconverged;
    // Every term is non-negative near the reference: a negative energy means that L-BFGS left
    // the physical basin (k_area < 0), and the Monte Carlo must not go on with it.
    if (tolerant && !(r.energy >= 0))
        throw std::runtime_error("L-BFGS left the physical minimum of a cluster (energy " + std::to_string(r.energy) +
                                 " < 0); use method='linear' or a smaller tol");
    return r;
}

}  // namespace pyfrustrate

namespace pyfrustrate {

// The Monte Carlo's relaxation settings (one per chain).
struct ClusterRelaxOptions {
    RelaxMethod method = RelaxMethod::Linear;
    MinimizeOptions minimize;  // absolute gradient tolerance, evaluation cap, step scale
    bool warm_start = true;    // L-BFGS starts from the linear solution (else the bulk reference)
    bool own_ldl = false;      // Newton: the kernel's own LDL^T on CHOLMOD's ordering (cholesky.hpp)
};

// Minimum deformation energy of a Monte Carlo cluster (main text Eq. 7, inner minimisation) by
// the policy above, tolerating floppy topologies (L-BFGS). Newton only: `start` (optional) is a
// warm start, `parent` (optional) the relaxed cluster it came from; `displacement` (optional)
// receives the relaxed displacement, `factor` (optional) the cluster ready for its children.
template <class Model>
double relaxed_cluster_energy(const Model& model, const Topology& topology, const ClusterRelaxOptions& options,
                              RelaxCounters& counters, const Vector* start = nullptr, Vector* displacement = nullptr,
                              const RelaxedCluster* parent = nullptr,
                              std::shared_ptr<RelaxedCluster>* factor = nullptr) {
    if (displacement) displacement->resize(0);
    RelaxRequest request;
    request.method = options.method;
    request.minimize = options.minimize;
    const bool newton = options.method == RelaxMethod::Newton;
    request.start = newton ? start : nullptr;
    request.parent = newton ? parent : nullptr;
    request.keep_factor = newton && factor;
    request.lbfgs_from_linear = options.warm_start;
    request.own_ldl = options.own_ldl;
    request.fall_back_to_lbfgs = true;
    RelaxExtras extras;
    const MinimizeResult r = relax_by_policy(model, topology, request, counters, nullptr, &extras);
    if (displacement && extras.method != RelaxMethod::Linear && r.energy >= 0) *displacement = r.displacement;
    if (factor) *factor = std::move(extras.factor);
    return r.energy;
}

}  // namespace pyfrustrate
