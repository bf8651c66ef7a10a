// The options of a Monte Carlo chain (montecarlo/chain.hpp) and their one table: each field's
// name, the values it takes, its default (the value in a default-made MonteCarloOptions) and what
// it means, listed once in for_each_option. The binding (bind_montecarlo.hpp) builds the chain's
// keywords, their checks, the constructor's documentation and the options' read-back from that
// table; Python's MonteCarloOptions (pyfrustrate/montecarlo/options.py) takes its fields,
// defaults and checks from it too. A new option is one member and one line of for_each_option.
#pragma once

#include "cluster_energy.hpp"

#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

namespace pyfrustrate {

// Metropolis acceptance of an energy change at temperature T with the uniform deviate u.
inline bool metropolis(double delta, double T, double u) { return delta <= 0 || (T > 0 && u < std::exp(-delta / T)); }

struct MonteCarloOptions {
    // Defaults: the best settings measured for annealing the paper's sparse box
    // (pyfrustrate.montecarlo.options.DEFAULTS_MEASURED says where), for anneal, replica_exchange,
    // the workflow and the kernel alike.
    ClusterRelaxOptions relax{RelaxMethod::Auto};
    double tol = 1e-3;          // relative: the chain relaxes to max gradient <= tol * force_scale
    double force_scale = 1.0;   // the particle's force unit (Python: particle.force_scale)
    // Delayed acceptance (Christen & Fox, J. Comput. Graph. Stat. 14, 795 (2005)): a move is
    // first screened with the surrogate energy E_s = -(g - bond_deformation) * bonds, accepted
    // there with min(1, exp(-dE_s / T)); only then are the clusters relaxed and the move
    // accepted with min(1, exp(-(dE - dE_s) / T)). E_s being a function of the configuration,
    // the chain still satisfies detailed balance with respect to exp(-E / T): same Boltzmann
    // distribution at every T, far fewer relaxations at low T (moves that break bonds are
    // mostly screened out). false: plain Metropolis, min(1, exp(-dE / T)).
    bool delayed_acceptance = true;
    double bond_deformation = 0.0;  // surrogate deformation energy per bond (bulk: e_b / bonds per particle)
    // The move families' probabilities and parameters, each explained in its header
    // (montecarlo/cluster_move.hpp, particle_move.hpp, surface_move.hpp). 0: the family is off
    // (no deviate drawn).
    double cluster_moves = 0.05;
    double cluster_link = 0.9;
    double bonded_moves = 0.5;
    double surface_moves = 0.2;
    // Collective isometry moves (montecarlo/isometry_move.hpp), off by default. The link 0.3 lies
    // below the triangular lattice's bond-percolation threshold 2 sin(pi/18) = 0.347, so that a
    // set grown inside an aggregate stays a local piece of it rather than the whole.
    double shift_moves = 0.0;
    double rotation_moves = 0.0;
    double reflection_moves = 0.0;
    double isometry_link = 0.3;
    // Vacancy moves (montecarlo/vacancy_move.hpp): holes filled and dug, off by default.
    double vacancy_moves = 0.0;
    // The carry (montecarlo/isometry_move.hpp), off by default: a set grown with cluster_link
    // translated by up to kCarryRadius neighbour steps.
    double carry_moves = 0.0;
    bool cache = true;        // cache relaxed energies by canonical shape
    bool incremental = true;  // false: re-minimise every cluster of the box on every move
                              // (the naive baseline of the benchmark; no cache either)
    std::size_t cache_limit = std::size_t(1) << 24;  // stored key entries (8 bytes each) before the cache is cleared
    // Newton only: relax the clusters a move makes from the relaxed displacements of the
    // clusters they came from (the particles that stay keep their corners' displacements, the
    // moved one starts rigidly attached), exact Hessian from the first step; the cluster is
    // relaxed as it lies rather than as its canonical representative. Energies then agree with
    // the cold start (the linear solution of the canonical representative) to the solver's
    // tolerance, not to the last bit: they depend on the path (and on the cache) at that level.
    bool parent_start = false;
    // parent_start only: a cluster a move changes by at most
    // kMaxChangedParticles particles relaxes by chord steps on its parent cluster's factor,
    // modified (parent_factor.hpp), instead of factorising its own Hessian; each relaxed cluster
    // of at least parent_factor_min_particles particles keeps its factor for its children (one
    // per cluster of the box, dropped with it). false: the warm start alone (the baseline of
    // benchmarks/bench_mc_goals.py).
    bool parent_factor = false;
    int parent_factor_min_particles = 0;
    // Grand-canonical sampling of one aggregate (montecarlo/outline_move.hpp): the probability of
    // an outline move (insertion or deletion at the aggregate's outline) and the reservoir's
    // chemical potential, in the units of g. outline_moves > 0: the box must hold one connected
    // aggregate, and every move that would disconnect it is refused.
    double outline_moves = 0.0;
    double chemical_potential = 0.0;
};

// What values a field takes.
enum class OptionKind {
    Flag,     // true or false
    Real,     // a real number in [lo, hi] (lo_open: (lo, ...; hi_open: ..., hi))
    Integer,  // an integer in [lo, hi]
    Method,   // "auto", "newton", "lbfgs" or "linear" (RelaxMethod)
};

// Who sets a field: a run's options (Python's MonteCarloOptions, which checkpoints record), the
// caller from the particle (its units), or a benchmark's baseline (kernel callers only).
enum class OptionScope { Run, Particle, Benchmark };

struct OptionField {
    const char* name;
    OptionKind kind;
    OptionScope scope;
    const char* doc;
    double lo = 0, hi = 0;
    bool lo_open = false, hi_open = false;
};

constexpr double kUnbounded = std::numeric_limits<double>::infinity();
constexpr double kIntMax = std::numeric_limits<int>::max();

inline OptionField flag(const char* name, OptionScope scope, const char* doc) {
    return {name, OptionKind::Flag, scope, doc};
}
inline OptionField real(const char* name, OptionScope scope, double lo, bool lo_open, double hi, bool hi_open,
                        const char* doc) {
    return {name, OptionKind::Real, scope, doc, lo, hi, lo_open, hi_open};
}
inline OptionField integer(const char* name, OptionScope scope, double lo, double hi, const char* doc) {
    return {name, OptionKind::Integer, scope, doc, lo, hi};
}

// Every option, in the order of Python's MonteCarloOptions, handed to f(field, member) with the
// member of `o` (or of o.relax) that holds it. The one list of the options.
template <class Options, class F>
void for_each_option(Options& o, F&& f) {
    using S = OptionScope;
    f(OptionField{"method", OptionKind::Method, S::Run,
                  "cluster relaxation: 'auto' (Newton, as pf.relax), 'newton', 'lbfgs', or 'linear' (the linearised "
                  "solve alone, biased upwards for loosely bound clusters)"},
      o.relax.method);
    f(real("tol", S::Run, 0, true, kUnbounded, true,
           "relaxation tolerance relative to the force scale: max gradient <= tol * force_scale"),
      o.tol);
    f(integer("max_iter", S::Run, 1, kIntMax, "energy evaluations per L-BFGS relaxation"),
      o.relax.minimize.max_iterations);
    f(flag("warm_start", S::Run,
           "warm starts: L-BFGS from the linear solution (else the bulk reference); with Newton, MonteCarloOptions "
           "turns parent_start on (from the parents' relaxed displacements)"),
      o.relax.warm_start);
    f(flag("delayed_acceptance", S::Run, "screen each move with the bond count before relaxing (Christen & Fox 2005)"),
      o.delayed_acceptance);
    f(real("cluster_moves", S::Run, 0, false, 1, false,
           "probability of a cluster move: a set grown from a random particle along bonds, shifted by a lattice vector"),
      o.cluster_moves);
    f(real("cluster_link", S::Run, 0, false, 1, false,
           "probability of following each bond when growing a moved cluster (1: whole clusters, rejected on contact)"),
      o.cluster_link);
    // At 1 a particle could never leave an aggregate.
    f(real("bonded_moves", S::Run, 0, false, 1, true,
           "probability that a particle move targets an empty site next to another particle"),
      o.bonded_moves);
    // At 1 a gas particle could never leave its spot.
    f(real("surface_moves", S::Run, 0, false, 1, true,
           "probability that a non-cluster move takes a particle with an empty neighbour next to another particle"),
      o.surface_moves);
    f(flag("cache", S::Run, "cache relaxed cluster energies by canonical shape (speed only)"), o.cache);
    f(flag("parent_factor", S::Run,
           "with parent_start (MonteCarloOptions: Newton with warm_start): a cluster a move changes by a few particles "
           "relaxes on its parent's modified factor"),
      o.parent_factor);
    f(integer("parent_factor_min_particles", S::Run, 0, kIntMax,
              "the smallest relaxed cluster that keeps its factor for its children"),
      o.parent_factor_min_particles);
    f(real("outline_moves", S::Run, 0, false, 1, false,
           "probability of an outline move: a particle inserted next to the one aggregate of the box or removed "
           "from it, exchanged with a reservoir at chemical_potential (other moves may not disconnect the aggregate)"),
      o.outline_moves);
    f(real("chemical_potential", S::Run, -kUnbounded, true, kUnbounded, true,
           "the reservoir's chemical potential mu of outline moves, in the units of g (the chain samples "
           "exp(-(E - mu n) / T))"),
      o.chemical_potential);
    f(real("vacancy_moves", S::Run, 0, false, 1, false,
           "probability of a vacancy move: a particle with an empty neighbour to a hole (an empty site with every "
           "neighbour occupied), or a particle with every neighbour occupied to an empty site next to the outline"),
      o.vacancy_moves);
    f(real("shift_moves", S::Run, 0, false, 1, false,
           "probability of a shift move: a linked set (grown with isometry_link) moved to a neighbouring site"),
      o.shift_moves);
    f(real("rotation_moves", S::Run, 0, false, 1, false,
           "probability of a rotation move: a linked set turned by +-60 degrees about its seed particle's site"),
      o.rotation_moves);
    f(real("reflection_moves", S::Run, 0, false, 1, false,
           "probability of a reflection move: a linked set mirrored about an axis through its seed particle's site"),
      o.reflection_moves);
    f(real("carry_moves", S::Run, 0, false, 1, false,
           "probability of a carry move: a linked set grown with cluster_link (a disk, a lobe) translated by a cell "
           "vector of at most three neighbour steps"),
      o.carry_moves);
    f(real("isometry_link", S::Run, 0, false, 1, false,
           "probability of following each bond when growing the set of a shift, rotation or reflection move"),
      o.isometry_link);
    f(real("force_scale", S::Particle, 0, true, kUnbounded, true, "the particle's force unit (particle.force_scale)"),
      o.force_scale);
    f(real("bond_deformation", S::Particle, -kUnbounded, true, kUnbounded, true,
           "the surrogate's deformation energy per bond (bulk energy per particle over bonds per bulk particle)"),
      o.bond_deformation);
    f(flag("parent_start", S::Particle,
           "Newton: relax each new cluster from its parents' relaxed displacements, exact Hessian from the first step"),
      o.parent_start);
    f(flag("incremental", S::Benchmark, "false: re-minimise every cluster of the box on every move (no cache either)"),
      o.incremental);
    f(integer("cache_limit", S::Benchmark, 1, 9.0e15, "stored cache key entries before the cache is cleared"),
      o.cache_limit);
}

inline std::string number_text(double x) {
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    std::string s = std::to_string(x);
    if (s.find('.') != std::string::npos) {
        s.erase(s.find_last_not_of('0') + 1);
        if (s.back() == '.') s.pop_back();
    }
    return s;
}

// The values a field takes, as its error message says them.
inline std::string range_text(const OptionField& f) {
    switch (f.kind) {
        case OptionKind::Flag: return "True or False";
        case OptionKind::Method: return "'auto', 'newton', 'lbfgs' or 'linear'";
        case OptionKind::Integer:
            return "an integer in [" + number_text(f.lo) + ", " + number_text(f.hi) + "]";
        case OptionKind::Real:
            break;
    }
    if (f.lo == -kUnbounded && f.hi == kUnbounded) return "a finite number";
    if (f.hi == kUnbounded) return std::string("a finite number ") + (f.lo_open ? "> " : ">= ") + number_text(f.lo);
    return std::string("a number in ") + (f.lo_open ? "(" : "[") + number_text(f.lo) + ", " + number_text(f.hi) +
           (f.hi_open ? ")" : "]");
}

// ValueError (through pybind11) naming the field, its range and the value given.
[[noreturn]] inline void refuse_option(const OptionField& f, const std::string& given) {
    throw std::invalid_argument(std::string(f.name) + " must be " + range_text(f) + ", got " + given);
}

inline bool in_range(const OptionField& f, double x) {
    if (!std::isfinite(x)) return false;
    return (f.lo_open ? x > f.lo : x >= f.lo) && (f.hi_open ? x < f.hi : x <= f.hi);
}

inline const char* method_name(RelaxMethod m) {
    switch (m) {
        case RelaxMethod::Linear: return "linear";
        case RelaxMethod::Lbfgs: return "lbfgs";
        case RelaxMethod::Newton: return "newton";
        case RelaxMethod::Auto: break;
    }
    return "auto";
}

inline RelaxMethod method_named(const OptionField& f, const std::string& name) {
    for (const RelaxMethod m : {RelaxMethod::Auto, RelaxMethod::Newton, RelaxMethod::Lbfgs, RelaxMethod::Linear})
        if (name == method_name(m)) return m;
    refuse_option(f, "'" + name + "'");
}

// What the chain runs from checked options: "auto" resolved (Newton, as pf.relax for one
// aggregate: the chain's warm starts are Newton's), the absolute tolerance, the particle's step
// scale. Refuses parent_start without Newton, parent_factor without parent_start.
inline MonteCarloOptions chain_settings(MonteCarloOptions o, double step_scale) {
    if (o.relax.method == RelaxMethod::Auto) o.relax.method = RelaxMethod::Newton;
    if (o.parent_start && o.relax.method != RelaxMethod::Newton)
        throw std::invalid_argument("parent_start needs method='newton' (or 'auto'), got method='" +
                                    std::string(method_name(o.relax.method)) + "'");
    if (o.parent_factor && !o.parent_start) throw std::invalid_argument("parent_factor needs parent_start");
    o.relax.minimize.gradient_tolerance = o.tol * o.force_scale;
    o.relax.minimize.step_scale = step_scale;
    o.relax.own_ldl = o.parent_start;  // the warm path factorises with the kernel's own LDL^T
    return o;
}

// parent_start: a moved particle whose known corners lie farther than this many step_scale
// (the mismatch) from the rigid fit makes the start cold. Measured in the dense box (300 in
// 30 x 30, ell = 5, nu = 0.4, 200 sweeps), factorisations per minimisation: 4.98 at 0.3, 5.00
// at 1, 4.82 at 3, 5.42 without a limit, 6.23 with cold starts only.
constexpr double kWarmMisfit = 3.0;

}  // namespace pyfrustrate
