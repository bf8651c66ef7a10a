// Bindings of the Monte Carlo annealing (montecarlo/chain.hpp): one class per particle model from
// this one template, and the factory _kernel.MonteCarlo(model, ...) overloaded on the model.
#pragma once

#include "bind_sites.hpp"
#include "montecarlo/chain.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

namespace pyfrustrate {

// A state of a chain for Python: the value (montecarlo/state.hpp) with the box and tiling its
// site numbers refer to.
struct BoundState {
    ChainState state;
    const Tiling* tiling = nullptr;
    int L = 0;
};

template <class F, std::size_t... I>
void for_each_move_counter(MoveCounters& counters, F& f, std::index_sequence<I...>) {
    (std::get<I>(counters).for_each([&](const char* name, std::int64_t& v) {
         f(std::string(std::tuple_element_t<I, MoveFamilies>::kName) + "_" + name, v);
     }),
     ...);
}

// Every counter of a state, named once (ChainCounters and each move family's, prefixed by the
// family's name), handed to f(name, value).
template <class F>
void for_each_counter(ChainState& s, F&& f) {
    s.counters.for_each([&](const char* name, std::int64_t& v) { f(std::string(name), v); });
    for_each_move_counter(s.move_counters, f, std::make_index_sequence<std::tuple_size_v<MoveFamilies>>{});
}

inline pybind11::dict counters_dict(ChainState& s) {
    pybind11::dict d;
    for_each_counter(s, [&](const std::string& name, std::int64_t& v) { d[name.c_str()] = v; });
    return d;
}

// The chain of one model and the state it is at, for Python: `run` passes the state into the
// chain and takes the one it returns (montecarlo/chain.hpp); nothing sets a part of it.
template <class Model>
struct BoundChain {
    MonteCarlo<Model> chain;
    ChainState state;
    int n() const { return static_cast<int>(state.particles.size()); }
};

template <class Model>
void export_montecarlo(pybind11::module_& m, const char* class_name) {
    namespace py = pybind11;
    using MC = BoundChain<Model>;
    py::class_<MC>(m, class_name,
                   "Metropolis Monte Carlo on the topology of N particles in a periodic L x L box of cells of the "
                   "particle's tiling (main text, 'Monte-Carlo validation of the phase diagram'). Energy = sum over "
                   "clusters of -g * bonds + relaxed deformation energy; relaxed energies are cached by shape up to "
                   "translations and the symmetries the particle and the tiling share.")
        .def(py::init([](const Model& model, double g, int box, int n, std::uint64_t seed, const std::string& method,
                         double tol, int max_iter, bool cache, bool warm_start, bool incremental, std::size_t cache_limit,
                         bool delayed_acceptance, double bond_deformation, double cluster_moves, double cluster_link, double bonded_moves,
                         double surface_moves, bool parent_start, bool parent_factor, int parent_factor_min_particles,
                         const std::optional<BoundState>& state) {
                 MonteCarloOptions o;
                 if (method == "linear") o.relax.method = RelaxMethod::Linear;
                 else if (method == "lbfgs") o.relax.method = RelaxMethod::Lbfgs;
                 else if (method == "newton") o.relax.method = RelaxMethod::Newton;
                 else throw std::invalid_argument("method must be 'linear', 'lbfgs' or 'newton', got '" + method + "'");
                 if (!(tol > 0)) throw std::invalid_argument("tol must be positive");
                 if (max_iter < 1) throw std::invalid_argument("max_iter must be at least 1");
                 o.relax.minimize.gradient_tolerance = tol;
                 o.relax.minimize.max_iterations = max_iter;
                 o.relax.minimize.step_scale = model.step_scale();
                 o.relax.warm_start = warm_start;
                 o.cache = cache;
                 o.incremental = incremental;
                 o.cache_limit = cache_limit;
                 if (!std::isfinite(bond_deformation)) throw std::invalid_argument("bond_deformation must be finite");
                 o.delayed_acceptance = delayed_acceptance;
                 o.bond_deformation = bond_deformation;
                 if (!(cluster_moves >= 0 && cluster_moves <= 1))
                     throw std::invalid_argument("cluster_moves must lie in [0, 1], got " + std::to_string(cluster_moves));
                 o.cluster_moves = cluster_moves;
                 if (!(cluster_link >= 0 && cluster_link <= 1))
                     throw std::invalid_argument("cluster_link must lie in [0, 1], got " + std::to_string(cluster_link));
                 o.cluster_link = cluster_link;
                 if (!(bonded_moves >= 0 && bonded_moves < 1))  // at 1 a particle could never leave an aggregate
                     throw std::invalid_argument("bonded_moves must lie in [0, 1), got " + std::to_string(bonded_moves));
                 o.bonded_moves = bonded_moves;
                 if (!(surface_moves >= 0 && surface_moves < 1))  // at 1 a gas particle could never leave its spot
                     throw std::invalid_argument("surface_moves must lie in [0, 1), got " + std::to_string(surface_moves));
                 o.surface_moves = surface_moves;
                 if (parent_start && o.relax.method != RelaxMethod::Newton)
                     throw std::invalid_argument("parent_start needs method='newton'");
                 o.parent_start = parent_start;
                 if (parent_factor && !parent_start) throw std::invalid_argument("parent_factor needs parent_start");
                 if (parent_factor_min_particles < 0)
                     throw std::invalid_argument("parent_factor_min_particles must be non-negative, got " +
                                                 std::to_string(parent_factor_min_particles));
                 o.parent_factor = parent_factor;
                 o.parent_factor_min_particles = parent_factor_min_particles;
                 o.relax.own_ldl = parent_start;  // the warm path factorises with the kernel's own LDL^T
                 auto* mc = new MC{MonteCarlo<Model>(model, g, box, o), ChainState{}};
                 if (!state) {
                     mc->state = mc->chain.initial_state(n, seed);
                     return mc;
                 }
                 if (std::string(state->tiling->name) != std::string(mc->chain.box().tiling->name) || state->L != box || static_cast<int>(state->state.particles.size()) != n)
                     throw std::invalid_argument("state: a state of " + std::to_string(state->state.particles.size()) +
                                                 " particles in a box of " + std::to_string(state->L) + " does not fit " +
                                                 std::to_string(n) + " in " + std::to_string(box));
                 ChainState given = state->state;
                 given.chain_id = 0;  // from elsewhere: the chain derives its bonds and clusters (a run of no move)
                 std::int64_t none = 0;
                 mc->state = mc->chain.run(std::move(given), 0.0, 0, none);
                 return mc;
             }),
             py::arg("model"), py::arg("g"), py::arg("box"), py::arg("n"), py::arg("seed"), py::arg("method") = "linear",
             py::arg("tol") = 1e-7, py::arg("max_iter") = 100000, py::arg("cache") = true, py::arg("warm_start") = true,
             py::arg("incremental") = true, py::arg("cache_limit") = std::size_t(1) << 24,
             py::arg("delayed_acceptance") = true, py::arg("bond_deformation") = 0.0, py::arg("cluster_moves") = 0.0,
             py::arg("cluster_link") = 1.0, py::arg("bonded_moves") = 0.0, py::arg("surface_moves") = 0.0,
             py::arg("parent_start") = false, py::arg("parent_factor") = false, py::arg("parent_factor_min_particles") = 0,
             py::arg("state") = py::none(),
             "Random initial placement drawn from the seeded std::mt19937_64, or the given state (a MonteCarloState of this box). tol is the absolute L-BFGS gradient "
             "tolerance (NLopt works in units of the model's step_scale); cache_limit the stored key entries before the cache is cleared; delayed_acceptance screens "
             "moves with the surrogate energy -(g - bond_deformation) * bonds before relaxing anything (same "
             "Boltzmann distribution); cluster_moves is the probability of a cluster translation: a set grown from "
             "a random particle by following each bond with probability cluster_link, shifted by a random lattice vector "
             "and accepted with the Metropolis-Hastings ratio (cluster_link = 1: whole clusters, rejected on any overlap or "
             "new contact, so shape and energy unchanged; below 1 aggregates can merge and split); bonded_moves is the probability that a particle move "
             "targets an empty site next to another particle (aggregation-volume-bias, with its Hastings ratio); surface_moves is the probability that a non-cluster move takes a random particle with an empty neighbour to a random empty site next to a particle (with its Hastings ratio); parent_start (method='newton') relaxes the clusters a move makes "
             "from the relaxed displacements of the clusters they came from, exact Hessian from the first step (energies "
             "equal the cold start's to the tolerance, not to the last bit); parent_factor (with parent_start) relaxes a cluster "
             "a move changes by a few particles by chord steps on its parent cluster's modified factor, kept by clusters of at "
             "least parent_factor_min_particles particles; incremental=False re-minimises every cluster of the box on every move.")
        .def(
            "run",
            [](MC& mc, py::array_t<double, py::array::c_style | py::array::forcecast> temperatures,
               py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> steps, bool record_sites) {
                if (temperatures.ndim() != 1 || steps.ndim() != 1 || temperatures.shape(0) != steps.shape(0))
                    throw std::invalid_argument("temperatures and steps must be 1D arrays of equal length");
                const py::ssize_t blocks = temperatures.shape(0);
                auto T = temperatures.unchecked<1>();
                auto S = steps.unchecked<1>();
                for (py::ssize_t k = 0; k < blocks; ++k) {
                    if (!(T(k) >= 0) || !std::isfinite(T(k)))
                        throw std::invalid_argument("temperatures must be non-negative and finite");
                    if (S(k) < 0) throw std::invalid_argument("steps must be non-negative");
                }
                py::array_t<double> energy(blocks);
                py::array_t<std::int64_t> accepted(blocks);
                py::array_t<int> sites(std::vector<py::ssize_t>{record_sites ? blocks : 0, mc.n()});
                auto E = energy.mutable_unchecked<1>();
                auto A = accepted.mutable_unchecked<1>();
                auto W = sites.mutable_unchecked<2>();
                {
                    py::gil_scoped_release release;
                    std::vector<int> sorted;
                    for (py::ssize_t k = 0; k < blocks; ++k) {
                        std::int64_t a = 0;
                        mc.state = mc.chain.run(std::move(mc.state), T(k), S(k), a);
                        A(k) = a;
                        E(k) = mc.chain.energy(mc.state);
                        if (!record_sites) continue;
                        sorted = mc.state.particles;
                        std::sort(sorted.begin(), sorted.end());
                        for (int p = 0; p < mc.n(); ++p) W(k, p) = sorted[p];
                    }
                }
                py::dict d;
                d["energy"] = energy;
                d["accepted"] = accepted;
                if (record_sites) d["sites"] = sites;
                return d;
            },
            py::arg("temperatures"), py::arg("steps"), py::arg("record_sites") = false,
            "Runs blocks of steps[k] attempted moves at temperatures[k] (GIL released). Returns a dict: energy (B,) "
            "after each block, accepted (B,) moves per block, and with record_sites the sorted occupied site indices "
            "(B, n) (site index sublattice + S (i + L j) for S sublattices per cell) after each block.")
        .def_property_readonly("energy", [](const MC& mc) { return mc.chain.energy(mc.state); },
                               "Running energy: -g * bonds + deformation.")
        .def_property_readonly("deformation", [](const MC& mc) { return mc.state.deformation; },
                               "Running sum of relaxed deformation energies.")
        .def_property_readonly("bonds", [](const MC& mc) { return mc.state.bonds; }, "Bound pairs of sides in the box.")
        .def_property_readonly("g", [](const MC& mc) { return mc.chain.g(); })
        .def_property_readonly("n", &MC::n)
        .def_property_readonly("box", [](const MC& mc) { return mc.chain.box().L; })
        .def("box_energy", [](MC& mc, bool canonical) { return mc.chain.box_energy(mc.state, canonical); },
             py::arg("canonical") = true,
             "Energy recomputed from scratch over every cluster, without the cache (canonical=False: from the "
             "sites as they lie, not from the canonical representative of each shape).")
        .def_property_readonly(
            "particles",
            [](const MC& mc) {
                std::vector<Site> sites;
                for (const int s : mc.state.particles) sites.push_back(mc.chain.box().coords(s));
                return sites_to_array(*mc.chain.box().tiling, sites);
            },
            "(n, 2) cells (0 <= i, j < box) of each particle, in particle order; (n, 3) with the sublattice for "
            "tilings with several.")
        .def("place",
             [](MC& mc, const SiteArray& sites) {
                 mc.state = mc.chain.place(std::move(mc.state), sites_from_array(*mc.chain.box().tiling, sites));
             },
             py::arg("sites"),
             "Puts particle p on sites[p] (as `particles`, reduced modulo the box): a configuration to start from, "
             "energy from scratch, no relaxed displacements known; generator and counters kept.")
        .def_property_readonly("shape_symmetries", [](const MC& mc) { return mc.chain.shape_symmetries(); },
                               "Lattice point operations under which cluster shapes share their energy (shape_key.hpp).")
        .def_property_readonly(
            "state", [](const MC& mc) { return BoundState{mc.state, mc.chain.box().tiling, mc.chain.box().L}; },
            "The chain's state, a value (MonteCarloState): pass it as MonteCarlo(..., state=) to continue the chain.")
        .def_property_readonly(
            "counters", [](MC& mc) { return counters_dict(mc.state); },
            "attempted, accepted, screened (rejected by the surrogate), cluster_attempted, cluster_accepted (cluster "
            "translations, counted in attempted/accepted too), cluster_rebonded (accepted translations that made or "
            "broke bonds), surface_attempted, surface_accepted (surface moves, within attempted/accepted), cache_hits, "
            "cache_misses, cache_clears, minimisations, evaluations (energy+gradient evaluations, 1 per linear "
            "solve), fallbacks (linear solve refused, done by L-BFGS), unconverged, factorizations, warm_starts "
            "(Newton from the parents' relaxed state), warm_restarts (of those, redone from the linear solution).")
        .def_property_readonly("cache_size", [](const MC& mc) { return mc.chain.cache_size(); })
        .def("clear_cache", [](MC& mc) { mc.chain.clear_cache(); });
    // The factory: pybind11 picks the class of the model passed.
    m.def(
        "MonteCarlo",
        [cls = m.attr(class_name)](const Model& model, py::args args, py::kwargs kwargs) {
            return cls(model, *args, **kwargs);
        },
        py::arg("model"), "MonteCarlo(model, g, box, n, seed, ...): the Monte Carlo class of the model's type.");
}

}  // namespace pyfrustrate
