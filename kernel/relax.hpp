// Minimising a network's energy at fixed topology (main text Eq. 7, the inner minimisation).
//
//   relax_linear   one solve with the eps = 0 reference stiffness: the linear response, exact as
//                  eps -> 0 (energy error O(eps^2) relative)
//   relax_newton   the nonlinear minimum to round-off: quasi-Newton steps on the reference
//                  stiffness while they are the cheaper way, then the exact Hessian (period-map
//                  curvature included, damped where indefinite), each step with a backtracking
//                  line search that guarantees descent; strongly nonlinear scenes go to L-BFGS
//   relax_lbfgs    NLopt's L-BFGS (the design's named minimiser); when it stops short of the
//                  tolerance (ftol, xtol, roundoff), Newton steps finish the job
//
// All work on the displacement u = x - x_ref (network.hpp) and share a StiffnessCache: the
// Hessian's sparsity pattern and CHOLMOD's symbolic analysis, made once per topology, and the
// factorised reference stiffness, made once per (particle stiffness, topology). A caller that
// relaxes one topology many times owns a cache and passes it; otherwise each call makes one.
#pragma once

#include "cholesky.hpp"
#include "minimize.hpp"
#include "network.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

namespace pyfrustrate {

// Each site's particle in a list of distinct sites (a topology's), -1 for a site not in it.
// A table over the sites' bounding box answers with one load; it is used where the box holds at
// most some tens of times as many sites as there are particles (an aggregate, a loose cluster),
// else a sorted list searched by bisection. With a std::map and a sorted list of (site, particle) pairs, the
// look-ups of rigid_pieces and of the parent's matching (modified_cluster) were the largest item
// of a relaxation from the parent's factor of an 817-particle disk (perf, bench_parent_relax).
class SiteLookup {
   public:
    SiteLookup(const std::vector<Site>& sites, int sublattices) : sublattices_(sublattices) {
        if (sites.empty()) return;
        long i_min = sites[0][0], i_max = i_min, j_min = sites[0][1], j_max = j_min;
        for (const Site& s : sites) {
            i_min = std::min<long>(i_min, s[0]), i_max = std::max<long>(i_max, s[0]);
            j_min = std::min<long>(j_min, s[1]), j_max = std::max<long>(j_max, s[1]);
        }
        const long width = i_max - i_min + 1, height = j_max - j_min + 1;
        const long n = static_cast<long>(sites.size());
        const long most_slots = 32 * n + 1024;  // the table's fill costs about as much as the look-ups then
        if (width <= most_slots && height <= most_slots && width * height * sublattices <= most_slots) {
            i0_ = i_min, j0_ = j_min, width_ = width, height_ = height;
            table_.assign(width * height * sublattices, -1);
            for (int p = 0; p < static_cast<int>(sites.size()); ++p) {
                int& slot = table_[slot_of(sites[p])];
                if (slot < 0) slot = p;
            }
        } else {
            sorted_.reserve(sites.size());
            for (int p = 0; p < static_cast<int>(sites.size()); ++p) sorted_.emplace_back(sites[p], p);
            std::sort(sorted_.begin(), sorted_.end());
        }
    }
    int operator()(const Site& s) const {
        if (!table_.empty()) {
            const long i = s[0] - i0_, j = s[1] - j0_;
            if (i < 0 || i >= width_ || j < 0 || j >= height_ || s[2] < 0 || s[2] >= sublattices_) return -1;
            return table_[slot_of(s)];
        }
        const auto it = std::lower_bound(sorted_.begin(), sorted_.end(), std::make_pair(s, -1));
        return it != sorted_.end() && it->first == s ? it->second : -1;
    }

   private:
    long slot_of(const Site& s) const { return ((s[0] - i0_) * height_ + (s[1] - j0_)) * sublattices_ + s[2]; }
    int sublattices_;
    long i0_ = 0, j0_ = 0, width_ = 0, height_ = 0;
    std::vector<int> table_;
    std::vector<std::pair<Site, int>> sorted_;
};

// Degrees of freedom held fixed to remove the three rigid-body zero modes (two translations
// and a rotation, which also turns the period vectors): corner 0, and the coordinate of the
// corner farthest from it that a rotation about corner 0 moves most. Where every corner of a
// periodic cell sits at one point (the triangle bulk: one vertex, its yellow and red node), the
// rotation shows only in the period vectors: the first one's transverse component is pinned.
inline std::vector<int> rigid_body_pins(const Topology& t) {
    int far = 0;
    double best = -1;
    for (int c = 1; c < t.n_corners(); ++c) {
        const double d = (t.reference[c] - t.reference[0]).squaredNorm();
        if (d > best) best = d, far = c;
    }
    if (best < 1e-12 && t.periodicity != Periodicity::None) {
        const Eigen::Vector2d p = t.reference_period_parameters().head<2>();
        return {0, 1, 2 * t.n_corners() + (std::abs(p.x()) >= std::abs(p.y()) ? 1 : 0)};
    }
    const Eigen::Vector2d d = t.reference[far] - t.reference[0];
    return {0, 1, 2 * far + (std::abs(d.x()) >= std::abs(d.y()) ? 1 : 0)};
}

// Removes the rigid-body part of a displacement from the reference state: the mean
// translation of the corners, and a linearised rotation (of corners about their centroid and of
// the period vectors). Which rotation is "zero" must not depend on how a scene is written down:
// for a periodic cell it is the one that keeps the first period vector's direction (the fibre
// axis), for a finite aggregate the least-squares rotation about the centroid. A linearised
// rotation left in the state would be stretched by the nonlinear energy (angle squared).
inline void remove_rigid_motion(const Topology& t, Vector& displacement) {
    const int nc = t.n_corners();
    const Vector period_ref = t.reference_period_parameters();
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero(), shift = Eigen::Vector2d::Zero();
    for (int c = 0; c < nc; ++c) {
        centroid += t.reference[c];
        shift += displacement.segment<2>(2 * c);
    }
    centroid /= nc;
    shift /= nc;
    for (int c = 0; c < nc; ++c) displacement.segment<2>(2 * c) -= shift;

    auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
    double angle = 0;
    if (t.periodicity == Periodicity::None) {
        double moment = 0;
        for (int c = 0; c < nc; ++c) {
            const Eigen::Vector2d r = t.reference[c] - centroid;
            angle += cross(r, displacement.segment<2>(2 * c));
            moment += r.squaredNorm();
        }
        angle /= moment;
    } else {
        const Eigen::Vector2d axis = period_ref.head<2>();
        angle = cross(axis, displacement.segment<2>(2 * nc)) / axis.squaredNorm();
    }
    for (int c = 0; c < nc; ++c) {
        const Eigen::Vector2d r = t.reference[c] - centroid;
        displacement.segment<2>(2 * c) -= angle * Eigen::Vector2d(-r.y(), r.x());
    }
    const int n_vectors = t.n_period_vectors();
    for (int v = 0; v < n_vectors; ++v) {
        const Eigen::Vector2d p = period_ref.segment<2>(2 * v);
        displacement.segment<2>(2 * nc + 2 * v) -= angle * Eigen::Vector2d(-p.y(), p.x());
    }
}

// What every solve on one topology reuses. Owned by the caller (Python: pf.StiffnessCache), never
// global. The reference factor is keyed by the particle's stiffness at rest (the Hessian of the
// model without mismatch at the reference corners, which is all the eps = 0 stiffness depends
// on), so one cache serves any particle and refactorises (numerically only) when that changes.
class StiffnessCache {
   public:
    // own_ldl: factorise with the analysis' own LDL^T where CHOLMOD's is simplicial (cholesky.hpp).
    explicit StiffnessCache(const Topology& topology, bool own_ldl = false)
        : topology_(topology), pins_(rigid_body_pins(topology)), own_ldl_(own_ldl) {}

    const Topology& topology() const { return topology_; }
    const std::vector<int>& pins() const { return pins_; }
    int reference_factorizations() const { return reference_factorizations_; }

    template <class Model>
    const HessianPattern& pattern(const Network<Model>& net) {
        if (!pattern_) {
            pattern_ = std::make_unique<HessianPattern>(net.hessian_pattern(pins_));
            // Own LDL^T: the ordering from the graph of corners (and period vectors), the two
            // coordinates of each one node.
            std::vector<int> node_of;
            if (own_ldl_) {
                node_of.resize(pattern_->n_free);
                for (size_t d = 0; d < pattern_->free_index.size(); ++d)
                    if (pattern_->free_index[d] >= 0) node_of[pattern_->free_index[d]] = static_cast<int>(d / 2);
            }
            analysis_ = std::make_shared<CholeskyAnalysis>(pattern_->n_free, pattern_->column_start, pattern_->row,
                                                           own_ldl_, own_ldl_ ? &node_of : nullptr);
        }
        return *pattern_;
    }

    std::shared_ptr<CholeskyAnalysis> analysis() const { return analysis_; }
    std::recursive_mutex& mutex() { return mutex_; }

    // The factorised eps = 0 stiffness of `model`'s particle on this topology.
    template <class Model>
    const CholeskyFactor& reference(const Model& model) {
        const Model rest_model = model.without_mismatch();
        const Network<Model> rest{rest_model, topology_};
        const HessianPattern& pat = pattern(rest);
        typename Model::Hessian h = Model::Hessian::Zero();
        rest_model.energy_of_displacement(Model::Corners::Zero(), nullptr, &h);
        const std::vector<double> key(h.data(), h.data() + h.size());
        if (reference_ && key == reference_key_) return *reference_;
        reference_ = std::make_unique<CholeskyFactor>(analysis_);
        ++reference_factorizations_;
        if (!reference_->factorize(rest.hessian(Vector::Zero(rest.size()), pat, /*exact=*/false)) ||
            reference_->pivot_ratio() <= 1e-13) {
            reference_.reset();
            throw std::runtime_error(
                "linear solve: the stiffness matrix is not positive definite (the topology has a floppy mode "
                "or the parameters make the network unstable); use method='lbfgs'");
        }
        reference_key_ = key;
        return *reference_;
    }

    // Full vector (pinned entries 0) from the free entries and back.
    Vector to_free(const Vector& full) const {
        Vector out(pattern_->n_free);
        for (size_t i = 0; i < pattern_->free_index.size(); ++i)
            if (pattern_->free_index[i] >= 0) out[pattern_->free_index[i]] = full[i];
        return out;
    }
    Vector to_full(const Vector& free) const {
        Vector out = Vector::Zero(pattern_->free_index.size());
        for (size_t i = 0; i < pattern_->free_index.size(); ++i)
            if (pattern_->free_index[i] >= 0) out[i] = free[pattern_->free_index[i]];
        return out;
    }

   private:
    const Topology& topology_;
    std::vector<int> pins_;
    bool own_ldl_ = false;
    std::unique_ptr<HessianPattern> pattern_;
    std::shared_ptr<CholeskyAnalysis> analysis_;
    std::unique_ptr<CholeskyFactor> reference_;
    std::vector<double> reference_key_;
    int reference_factorizations_ = 0;
    std::recursive_mutex mutex_;
};

// The cache a call uses: the caller's, or one of its own.
// A given cache is locked for the call: relaxations release Python's GIL, and two threads
// sharing a cache take turns instead of racing on its factors (recursive: relax_newton hands its
// cache on to relax_lbfgs).
class CacheHandle {
   public:
    CacheHandle(const Topology& t, StiffnessCache* given) {
        if (given && &given->topology() != &t)
            throw std::invalid_argument("cache: it was made for another topology");
        if (given) lock_ = std::unique_lock<std::recursive_mutex>(given->mutex());
        if (!given) own_ = std::make_unique<StiffnessCache>(t);
        cache_ = given ? given : own_.get();
    }
    StiffnessCache& operator*() const { return *cache_; }
    StiffnessCache* operator->() const { return cache_; }

   private:
    std::unique_lock<std::recursive_mutex> lock_;
    std::unique_ptr<StiffnessCache> own_;
    StiffnessCache* cache_;
};

// K^-1 r with the reference stiffness factor k = cache.reference(model) (pinned entries 0).
inline Vector reference_solve(const StiffnessCache& cache, const CholeskyFactor& k, const Vector& residual) {
    const Vector step = k.solve(cache.to_free(residual));
    if (!step.allFinite()) throw std::runtime_error("linear solve: sparse Cholesky back-substitution failed");
    return cache.to_full(step);
}

// Linear response about the bulk reference: one Newton step with the reference stiffness,
// driven by the mismatch forces at the reference; the displacement without a linearised rotation.
template <class Model>
Vector linear_displacement(const Model& model, const Topology& topology, StiffnessCache& cache) {
    const Network<Model> net{model, topology};
    Vector gradient;
    net.energy(Vector::Zero(net.size()), &gradient);
    Vector u = -reference_solve(cache, cache.reference(model), gradient);
    remove_rigid_motion(topology, u);
    return u;
}

inline double max_abs(const Vector& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

// The result record at displacement u (positions in x).
template <class Model>
MinimizeResult result_at(const Network<Model>& net, const Vector& u) {
    MinimizeResult r;
    Vector gradient;
    r.energy = net.energy(u, &gradient);
    r.gradient_norm = max_abs(gradient);
    r.x = state_of(net.topology, u);
    r.displacement = u;
    return r;
}

// The linear response: exact as eps -> 0; its energy is the full nonlinear energy of that
// state, an upper bound on the minimum exact to O(eps^4).
template <class Model>
MinimizeResult relax_linear(const Model& model, const Topology& topology, StiffnessCache* given = nullptr) {
    CacheHandle cache(topology, given);
    const Network<Model> net{model, topology};
    MinimizeResult result = result_at(net, linear_displacement(model, topology, *cache));
    result.converged = std::isfinite(result.energy);
    result.iterations = 1;
    result.status = "linear solve";
    return result;
}

// One globalised step along a descent direction, shared by Newton and the parent factor's chord
// steps: a trust region (no corner moves by more than max_step, lattice units, in one step: a
// longer step comes from a model far from quadratic and could leave the physical basin, as
// k_area < 0 is unbounded below), then a backtracking line search taking the first of 1, 1/2,
// 1/4, ... that satisfies Armijo's condition or, once the predicted decrease falls below what the
// energy resolves (a sum of terms that may cancel: springs against areas with k_area < 0), that
// lowers the largest force, the merit function there. Forces on `pins` are held at zero.
// Returns whether a step was taken; the trial state is written to `next`.
struct LineSearchPoint {
    Vector u, gradient;
    double energy = 0, gnorm = 0;
};

template <class Net>
bool backtracking_step(const Net& net, const Vector& u, Vector direction, const Vector& gradient, double energy,
                       double gnorm, const MinimizeOptions& options, int& evaluations, const std::vector<int>& pins,
                       LineSearchPoint& next) {
    constexpr double armijo = 1e-4;
    constexpr double roundoff = 1e-10;  // relative resolution of the energy assumed near the minimum
    const double longest = max_abs(direction);
    if (longest > options.newton_max_step) direction *= options.newton_max_step / longest;
    const double slope = gradient.dot(direction);
    double length = 1.0;
    for (int halving = 0; halving < 40 && evaluations < options.max_iterations; ++halving, length *= 0.5) {
        next.u = u + length * direction;
        next.energy = net.energy(next.u, &next.gradient);
        ++evaluations;
        if (!std::isfinite(next.energy)) continue;
        for (const int d : pins) next.gradient[d] = 0;
        next.gnorm = max_abs(next.gradient);
        const bool decrease = next.energy <= energy + armijo * length * slope;
        const bool at_roundoff = -slope * length <= roundoff * std::abs(energy) && next.gnorm < gnorm;
        if (decrease || at_roundoff) return true;
    }
    return false;
}

// Newton from displacement u0. Directions: -K^-1 g with the reference stiffness K (factorised
// once, a solve per step; quasi-Newton pairs refine it, see below), or -H^-1 g with the exact Hessian H (one numeric factorisation per
// step on the shared analysis; where H is not positive definite, the reference direction). The
// reference steps contract the force linearly (by a ratio that grows with eps and near
// instabilities), exact ones quadratically; after each reference step the cheaper way to the
// tolerance is taken: the remaining reference steps at the ratio just measured, against about
// three exact steps, each a factorisation. Costs are counted in floating-point operations from
// CHOLMOD's analysis (a factorisation: its flop count; a reference step: two triangular sweeps,
// 4 nnz(L), and an evaluation, ~100 per degree of freedom), not in seconds, so that the path,
// and hence the result to the last digit, does not depend on the machine's load. Both
// directions descend (K and H positive definite on the free dof); a backtracking line search
// takes the first of 1, 1/2, 1/4, ... that satisfies Armijo's condition, or, once the predicted
// decrease is below 1e-10 of the energy, that lowers the largest force. Stops at the tolerance, at the
// evaluation cap, or when no step helps (round-off floor, reported as such).
template <class Model>
MinimizeResult newton_from(const Model& model, const Topology& topology, Vector u, const MinimizeOptions& options,
                           StiffnessCache& cache, int evaluations_before = 0) {
    const Network<Model> net{model, topology};
    const double switch_ratio = options.newton_switch_ratio;
    // The reference factor, made on first use: a start close to the minimum (options.
    // newton_exact_from_start) may need none.
    const CholeskyFactor* reference = nullptr;
    auto stiffness = [&]() -> const CholeskyFactor& {
        if (!reference) reference = &cache.reference(model);
        return *reference;
    };
    if (!options.newton_exact_from_start) stiffness();  // also makes the analysis used below
    Vector gradient;
    double energy = net.energy(u, &gradient);
    double gnorm = max_abs(gradient);
    int evaluations = evaluations_before + 1, steps = 0, factorizations = 0;
    bool exact = options.newton_exact_from_start;
    std::unique_ptr<CholeskyFactor> hessian;
    double shift = 0;  // Levenberg-Marquardt damping of the exact Hessian
    double best_gnorm = gnorm;
    struct Pair {
        Vector s, y;
        double rho;
    };
    std::vector<Pair> history;  // quasi-Newton pairs of the reference-stiffness steps
    int damped_steps = 0;
    bool handover = false;
    double runaway = 1.0;  // the aggregate's size: largest distance of a corner from corner 0, or a period
    for (const Vec2& r : topology.reference) runaway = std::max(runaway, (r - topology.reference[0]).norm());
    if (topology.n_period_parameters()) runaway += topology.reference_period_parameters().head<2>().norm();
    int stalled = 0;
    std::string stop;
    while (gnorm > options.gradient_tolerance) {
        if (max_abs(u) > runaway) {
            // A corner has moved by more than the aggregate's size: the network is not relaxing
            // but running away (k_area < 0 near the stability limit is unbounded below).
            stop = "runaway: a corner moved farther than the aggregate's size (the network is unstable)";
            break;
        }
        if (evaluations >= options.max_iterations) {
            stop = "maximum number of iterations reached";
            break;
        }
        Vector direction;
        if (exact) {
            // Where H is not positive definite (far from the minimum, or near an instability),
            // H + shift * diag(H): Levenberg-Marquardt's damping, raised tenfold until the
            // factorisation succeeds and relaxed a hundredfold after each step taken.
            const HessianPattern& pat = cache.pattern(net);
            if (!hessian) hessian = std::make_unique<CholeskyFactor>(cache.analysis());
            const std::vector<double> h = net.hessian(u, pat, /*exact=*/true);
            std::vector<double> damped = h;
            // A diagonal entry <= 0 stays so under this damping, and every attempt would fail
            // (an LDL^T pivot is at most its diagonal entry while the pivots before it are
            // positive): the shifts are raised as the failures would raise them, without the
            // factorisations (in a dense Monte Carlo run, 3 % of them were such attempts).
            bool hopeless = false;
            for (int j = 0; j < pat.n_free && !hopeless; ++j) hopeless = !(h[pat.column_start[j + 1] - 1] > 0);
            for (int attempt = 0; attempt < 30 && hopeless; ++attempt) shift = shift > 0 ? 10 * shift : 1e-4;
            for (int attempt = 0; attempt < 30 && !hopeless; ++attempt) {
                if (shift > 0)
                    for (int j = 0; j < pat.n_free; ++j) {
                        const int diagonal = pat.column_start[j + 1] - 1;  // rows sorted: last is j
                        damped[diagonal] = h[diagonal] * (1 + shift);
                    }
                ++factorizations;
                if (hessian->factorize(damped)) {
                    direction = -cache.to_full(hessian->solve(cache.to_free(gradient)));
                    break;
                }
                shift = shift > 0 ? 10 * shift : 1e-4;
            }
        }
        if (direction.size() == 0) {
            // Quasi-Newton on the reference stiffness: L-BFGS's two-loop recursion with K^-1 as
            // the initial inverse Hessian, over the last steps taken in this mode. K carries the
            // linear elasticity; the pairs learn the nonlinear rest, so the contraction per step
            // improves on the fixed-stiffness iteration (measured at R = 25, eps = 0.01: 5
            // instead of 6 steps to tol 1e-5, 10 instead of 13 to 1e-10). Pinned entries of s
            // are zero, so they stay out of every product.
            Vector q = gradient;
            std::vector<double> alpha(history.size());
            for (int i = static_cast<int>(history.size()) - 1; i >= 0; --i) {
                alpha[i] = history[i].rho * history[i].s.dot(q);
                q -= alpha[i] * history[i].y;
            }
            direction = reference_solve(cache, stiffness(), q);
            for (size_t i = 0; i < history.size(); ++i) {
                const double beta = history[i].rho * history[i].y.dot(direction);
                direction += (alpha[i] - beta) * history[i].s;
            }
            direction = -direction;
        }
        if (!(gradient.dot(direction) < 0) || !direction.allFinite()) {
            history.clear();
            direction = -reference_solve(cache, stiffness(), gradient);
        }
        LineSearchPoint next;
        const bool accepted = backtracking_step(net, u, direction, gradient, energy, gnorm, options, evaluations, {}, next);
        if (!accepted) {
            stop = evaluations >= options.max_iterations
                       ? "maximum number of iterations reached"
                       : "round-off floor: no step lowers the energy or the largest force";
            break;
        }
        ++steps;
        if (shift > 0) ++damped_steps;
        shift = shift > 1e-6 ? shift / 100 : 0;
        if (!exact) {
            Pair pair{next.u - u, next.gradient - gradient, 0.0};
            const double sy = pair.s.dot(pair.y);
            if (sy > 1e-12 * pair.s.norm() * pair.y.norm()) {
                pair.rho = 1.0 / sy;
                history.push_back(std::move(pair));
                if (history.size() > 5) history.erase(history.begin());
            }
        }
        const double previous_energy = energy, previous_gnorm = gnorm;
        u = std::move(next.u);
        energy = next.energy;
        gradient = std::move(next.gradient);
        gnorm = next.gnorm;
        if (options.newton_handover && damped_steps > 4 && gnorm > options.gradient_tolerance) {
            // Far from the minimum, where the Hessian stays indefinite (large eps, nu -> 1),
            // L-BFGS globalises better than damped Newton; Newton finishes after it.
            stop = "handed over to L-BFGS: the exact Hessian was indefinite in 5 steps";
            handover = true;
            break;
        }
        // Round-off: the force no longer falls (its noise is reached). Give up after eight exact
        // steps that neither lowered the energy beyond round-off nor the best force tenfold.
        const bool energy_still_falls = previous_energy - energy > 1e-13 * std::abs(previous_energy);
        if (gnorm < 0.1 * best_gnorm || energy_still_falls) {
            best_gnorm = std::min(best_gnorm, gnorm);
            stalled = 0;
        } else if (++stalled >= 8 && exact) {
            // A stall far above the tolerance is the landscape's doing, not round-off's.
            handover = options.newton_handover && gnorm > 1e4 * options.gradient_tolerance;
            stop = handover ? "handed over to L-BFGS: Newton stalled far from the tolerance"
                            : "round-off floor: the largest force stopped falling (its noise is reached)";
            break;
        }
        if (!exact && gnorm > options.gradient_tolerance) {
            const double ratio = gnorm / previous_gnorm;
            if (ratio > switch_ratio) {
                exact = true;
            } else {
                const CholeskyAnalysis& a = *cache.analysis();
                const double step_cost = 4.0 * a.factor_nonzeros() + 100.0 * a.size();
                const double factorization_cost = a.factor_flops() / step_cost;
                const double remaining = std::log(options.gradient_tolerance / gnorm) / std::log(ratio);
                exact = remaining > 3 * (factorization_cost + 1);
            }
        }
        if (exact) history.clear();
    }
    MinimizeResult result;
    result.x = state_of(topology, u);
    result.displacement = std::move(u);
    result.energy = energy;
    result.gradient_norm = gnorm;
    result.iterations = evaluations;
    result.newton_steps = steps;
    result.factorizations = factorizations;
    result.converged = gnorm <= options.gradient_tolerance;
    result.status = result.converged ? "gradient tolerance reached" : stop;
    result.handed_over = handover && !result.converged;
    return result;
}

template <class Model>
MinimizeResult relax_lbfgs(const Model& model, const Topology& topology, const Vector& x0,
                           const MinimizeOptions& options, StiffnessCache* given = nullptr);

// The nonlinear minimum by Newton steps from the linear response; where Newton hands over
// (strongly nonlinear scenes), L-BFGS from its last state, finished by Newton again.
// start: the displacement to start from instead (a warm start, e.g. a neighbouring relaxed state).
template <class Model>
MinimizeResult relax_newton(const Model& model, const Topology& topology, const MinimizeOptions& options,
                            StiffnessCache* given = nullptr, const Vector* start = nullptr) {
    CacheHandle cache(topology, given);
    Vector u0 = start ? *start : linear_displacement(model, topology, *cache);
    MinimizeResult r = newton_from(model, topology, std::move(u0), options, *cache);
    if (r.handed_over && r.iterations < options.max_iterations) {
        MinimizeOptions rest = options;
        rest.max_iterations = options.max_iterations - r.iterations;
        rest.newton_handover = false;
        MinimizeResult l = relax_lbfgs(model, topology, r.x, rest, &*cache);
        l.status = "newton (" + std::to_string(r.newton_steps) + " steps, " + r.status + "), then " + l.status;
        l.iterations += r.iterations;
        l.newton_steps += r.newton_steps;
        l.factorizations += r.factorizations;
        return l;
    }
    r.status = "newton: " + r.status;
    return r;
}

// NLopt L-BFGS from the state x0 (positions), in displacement variables. A run that ends above
// the tolerance on NLopt's own criteria (ftol, xtol, roundoff: its line search has run out of
// digits) is finished by Newton steps; the status says which did the work.
template <class Model>
MinimizeResult relax_lbfgs(const Model& model, const Topology& topology, const Vector& x0,
                           const MinimizeOptions& options, StiffnessCache* given) {
    const Network<Model> net{model, topology};
    if (x0.size() != net.size())
        throw std::invalid_argument("x0 has " + std::to_string(x0.size()) + " entries, the network has " +
                                    std::to_string(net.size()) + " degrees of freedom");
    const Objective objective = [&net](const Vector& u, Vector& g) { return net.energy(u, &g); };
    MinimizeResult r = minimize_lbfgs(objective, displacement_of(topology, x0), options);
    r.lbfgs_evaluations = r.iterations;
    const bool stopped_short = !r.converged && r.iterations < options.max_iterations &&
                               r.status != "non-finite energy or gradient" && options.finish_with_newton;
    if (stopped_short) {
        const std::string lbfgs_status = r.status;
        try {
            CacheHandle cache(topology, given);
            MinimizeOptions finish = options;
            finish.newton_handover = false;
            MinimizeResult n = newton_from(model, topology, r.x, finish, *cache, r.iterations);
            n.lbfgs_evaluations = r.lbfgs_evaluations;
            n.status = "L-BFGS stopped short (" + lbfgs_status + ") after " + std::to_string(r.iterations) +
                       " evaluations, then newton: " + n.status;
            if (n.energy <= r.energy || n.converged) return n;
        } catch (const std::runtime_error&) {
            r.status += " (no Newton finish: the stiffness is not positive definite)";
        }
    }
    r.displacement = r.x;
    r.x = state_of(topology, r.displacement);
    return r;
}

}  // namespace pyfrustrate
