// Bindings of the Monte Carlo annealing (montecarlo/chain.hpp): one class per particle model from
// this one template, and the factory _kernel.MonteCarlo(model, ...) overloaded on the model.
#pragma once

#include "bind_sites.hpp"
#include "montecarlo/chain.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <type_traits>
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
    (std::get<I>(counters).for_each([&](const char* name, std::int64_t& v, const char* meaning) {
         f(std::string(std::tuple_element_t<I, MoveFamilies>::kName) + "_" + name, v, meaning);
     }),
     ...);
}

// Every counter of a state, named and described once (ChainCounters and each move family's,
// prefixed by the family's name), handed to f(name, value, meaning).
template <class F>
void for_each_counter(ChainState& s, F&& f) {
    s.counters.for_each([&](const char* name, std::int64_t& v, const char* meaning) { f(std::string(name), v, meaning); });
    for_each_move_counter(s.move_counters, f, std::make_index_sequence<std::tuple_size_v<MoveFamilies>>{});
}

inline pybind11::dict counters_dict(ChainState& s) {
    pybind11::dict d;
    for_each_counter(s, [&](const std::string& name, std::int64_t& v, const char*) { d[name.c_str()] = v; });
    return d;
}

// The `counters` docstring, written from the counters themselves, so that a new move family's
// counters are documented by its header alone.
inline std::string counters_doc() {
    ChainState s;
    std::string doc = "Every counter of the chain, a dict name -> count:\n";
    for_each_counter(s, [&](const std::string& name, std::int64_t&, const char* meaning) {
        doc += "\n- ``" + name + "``: " + meaning;
    });
    return doc;
}

// The options' table (montecarlo/options.hpp) seen from Python: a value given for a field is
// read and checked against that field (ValueError naming it, its range and the value), a value
// read back is the Python object of its member.
inline std::string python_repr(pybind11::handle value) { return pybind11::repr(value).cast<std::string>(); }

inline void read_option(const OptionField& f, bool& member, pybind11::handle value) {
    if (!pybind11::isinstance<pybind11::bool_>(value)) refuse_option(f, python_repr(value));
    member = value.cast<bool>();
}

inline void read_option(const OptionField& f, double& member, pybind11::handle value) {
    if (pybind11::isinstance<pybind11::bool_>(value) || !PyNumber_Check(value.ptr())) refuse_option(f, python_repr(value));
    double x = 0;
    try {
        x = value.cast<double>();
    } catch (const pybind11::cast_error&) {
        refuse_option(f, python_repr(value));
    }
    if (!in_range(f, x)) refuse_option(f, python_repr(value));
    member = x;
}

template <class Int, std::enable_if_t<std::is_integral_v<Int> && !std::is_same_v<Int, bool>, int> = 0>
void read_option(const OptionField& f, Int& member, pybind11::handle value) {
    // An integer (Python's or numpy's, not a bool, not a float however round), within range.
    if (pybind11::isinstance<pybind11::bool_>(value) || !PyIndex_Check(value.ptr())) refuse_option(f, python_repr(value));
    const auto x = pybind11::reinterpret_steal<pybind11::int_>(PyNumber_Index(value.ptr()));
    const long double v = PyLong_AsDouble(x.ptr());
    if (PyErr_Occurred()) PyErr_Clear();
    if (!(v >= f.lo && v <= f.hi)) refuse_option(f, python_repr(value));
    member = static_cast<Int>(x.cast<long long>());
}

inline void read_option(const OptionField& f, RelaxMethod& member, pybind11::handle value) {
    if (!pybind11::isinstance<pybind11::str>(value)) refuse_option(f, python_repr(value));
    member = method_named(f, value.cast<std::string>());
}

inline pybind11::object option_value(bool v) { return pybind11::bool_(v); }
inline pybind11::object option_value(double v) { return pybind11::float_(v); }
inline pybind11::object option_value(int v) { return pybind11::int_(v); }
inline pybind11::object option_value(std::size_t v) { return pybind11::int_(v); }
inline pybind11::object option_value(RelaxMethod v) { return pybind11::str(method_name(v)); }

inline const char* scope_name(OptionScope s) {
    return s == OptionScope::Run ? "run" : s == OptionScope::Particle ? "particle" : "benchmark";
}

// Options from keywords: each one a field of the table, checked; the others their defaults.
// A keyword that is no field raises TypeError naming it.
inline MonteCarloOptions options_from_keywords(const pybind11::dict& keywords) {
    MonteCarloOptions o;
    std::size_t read = 0;
    std::string names;
    for_each_option(o, [&](const OptionField& f, auto& member) {
        names += std::string(names.empty() ? "" : ", ") + f.name;
        if (!keywords.contains(f.name)) return;
        read_option(f, member, keywords[f.name]);
        ++read;
    });
    if (read != keywords.size())
        for (const auto& item : keywords) {
            bool known = false;
            for_each_option(o, [&](const OptionField& f, auto&) { known = known || item.first.cast<std::string>() == f.name; });
            if (!known)
                throw pybind11::type_error("unexpected keyword argument " + python_repr(item.first) +
                                           "; the chain's options are " + names);
        }
    return o;
}

// Every field of `o` by name.
inline pybind11::dict options_dict(const MonteCarloOptions& o) {
    pybind11::dict d;
    for_each_option(o, [&](const OptionField& f, const auto& member) { d[f.name] = option_value(member); });
    return d;
}

// The table: one dict per field (name, kind, scope, default, range, doc), in its order.
inline pybind11::list option_fields() {
    pybind11::list fields;
    const MonteCarloOptions defaults;
    for_each_option(defaults, [&](const OptionField& f, const auto& member) {
        static const char* kinds[] = {"flag", "real", "integer", "method"};
        pybind11::dict d;
        d["name"] = f.name;
        d["kind"] = kinds[static_cast<int>(f.kind)];
        d["scope"] = scope_name(f.scope);
        d["default"] = option_value(member);
        d["range"] = range_text(f);
        d["doc"] = f.doc;
        fields.append(d);
    });
    return fields;
}

// The constructor's documentation, its keywords listed from the table.
inline const char* constructor_doc() {
    static const std::string doc = [] {
        std::string s =
            "Random initial placement drawn from the seeded std::mt19937_64, or the given state (a MonteCarloState of "
            "this box). The options are keywords, each a field of the kernel's table (monte_carlo_option_fields()), "
            "checked there (ValueError naming the field; TypeError for a keyword that is no field):";
        const MonteCarloOptions defaults;
        for_each_option(defaults, [&](const OptionField& f, const auto& member) {
            s += "\n\n" + std::string(f.name) + " (" + range_text(f) + ", default " +
                 python_repr(option_value(member)) + "): " + f.doc + ".";
        });
        return s;
    }();
    return doc.c_str();
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
        .def(py::init([](const Model& model, double g, int box, int n, std::uint64_t seed,
                         const std::optional<BoundState>& state, const py::kwargs& options) {
                 auto* mc = new MC{MonteCarlo<Model>(model, g, box, chain_settings(options_from_keywords(options), model.step_scale())),
                                   ChainState{}};
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
             py::arg("model"), py::arg("g"), py::arg("box"), py::arg("n"), py::arg("seed"), py::kw_only(),
             py::arg("state") = py::none(), constructor_doc())
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
                py::array_t<int> particles(blocks);
                auto E = energy.mutable_unchecked<1>();
                auto A = accepted.mutable_unchecked<1>();
                auto N = particles.mutable_unchecked<1>();
                std::vector<std::vector<int>> recorded(record_sites ? blocks : 0);
                {
                    py::gil_scoped_release release;
                    for (py::ssize_t k = 0; k < blocks; ++k) {
                        std::int64_t a = 0;
                        mc.state = mc.chain.run(std::move(mc.state), T(k), S(k), a);
                        A(k) = a;
                        E(k) = mc.chain.energy(mc.state);
                        N(k) = mc.n();
                        if (!record_sites) continue;
                        recorded[k] = mc.state.particles;
                        std::sort(recorded[k].begin(), recorded[k].end());
                    }
                }
                py::dict d;
                d["energy"] = energy;
                d["accepted"] = accepted;
                d["n"] = particles;
                if (record_sites) {
                    // Outline moves change the number of particles: rows padded with -1 to the largest.
                    py::ssize_t width = mc.n();
                    for (const auto& r : recorded) width = std::max(width, static_cast<py::ssize_t>(r.size()));
                    py::array_t<int> sites(std::vector<py::ssize_t>{blocks, width});
                    auto W = sites.mutable_unchecked<2>();
                    for (py::ssize_t k = 0; k < blocks; ++k)
                        for (py::ssize_t p = 0; p < width; ++p)
                            W(k, p) = p < static_cast<py::ssize_t>(recorded[k].size()) ? recorded[k][p] : -1;
                    d["sites"] = sites;
                }
                return d;
            },
            py::arg("temperatures"), py::arg("steps"), py::arg("record_sites") = false,
            "Runs blocks of steps[k] attempted moves at temperatures[k] (GIL released). Returns a dict: energy (B,) "
            "after each block, accepted (B,) moves per block, n (B,) particles after each block (outline moves change "
            "it), and with record_sites the sorted occupied site indices (B, max n) (site index sublattice + S (i + L "
            "j) for S sublattices per cell) after each block, rows padded with -1.")
        .def_property_readonly("energy", [](const MC& mc) { return mc.chain.energy(mc.state); },
                               "Running energy: -g * bonds + deformation.")
        .def_property_readonly("deformation", [](const MC& mc) { return mc.state.deformation; },
                               "Running sum of relaxed deformation energies.")
        .def_property_readonly("bonds", [](const MC& mc) { return mc.state.bonds; }, "Bound pairs of sides in the box.")
        .def_property_readonly("g", [](const MC& mc) { return mc.chain.g(); })
        .def_property_readonly(
            "options", [](const MC& mc) { return options_dict(mc.chain.options()); },
            "The options the chain runs with, every field of the table (montecarlo/options.hpp): 'auto' resolved.")
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
            counters_doc().c_str())
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
