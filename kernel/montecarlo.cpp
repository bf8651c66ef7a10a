#include "montecarlo.hpp"

#include "hexagon.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace pyfrustrate {

const std::array<LatticeVector, 6> kLatticeNeighbours{{{1, 0}, {0, 1}, {-1, 1}, {-1, 0}, {0, -1}, {1, -1}}};

namespace {

int floor_mod(int a, int m) {
    const int r = a % m;
    return r < 0 ? r + m : r;
}

int gcd(int a, int b) {
    a = std::abs(a), b = std::abs(b);
    while (b) {
        const int t = a % b;
        a = b, b = t;
    }
    return a;
}

// p a + q b = g = gcd(a, b) >= 0.
void extended_gcd(long a, long b, long& g, long& p, long& q) {
    long r0 = a, r1 = b, s0 = 1, s1 = 0, t0 = 0, t1 = 1;
    while (r1 != 0) {
        const long k = r0 / r1;
        long tmp = r0 - k * r1; r0 = r1; r1 = tmp;
        tmp = s0 - k * s1; s0 = s1; s1 = tmp;
        tmp = t0 - k * t1; t0 = t1; t1 = tmp;
    }
    if (r0 < 0) r0 = -r0, s0 = -s0, t0 = -t0;
    g = r0, p = s0, q = t0;
}

// Adds the wrap vector (x, y) to the lattice (a, b), (0, c) of the cluster, keeping the
// Hermite normal form: the new first row is the gcd combination of (a, b) and (x, y), the
// remainder (x/g)(a, b) - (a/g)(x, y) = (0, r) merges into c (a unimodular change of basis).
void add_wrap(Cluster& cl, int x, int y) {
    if (x == 0 && cl.a == 0) {
        cl.c = gcd(cl.c, y);
    } else {
        long g, p, q;
        extended_gcd(cl.a, x, g, p, q);
        const long b = p * cl.b + q * y;
        const long r = (x / g) * static_cast<long>(cl.b) - (cl.a / g) * static_cast<long>(y);
        cl.a = static_cast<int>(g);
        cl.b = static_cast<int>(b);
        cl.c = gcd(cl.c, static_cast<int>(r));
    }
    if (cl.c > 0) cl.b = floor_mod(cl.b, cl.c);
}

constexpr std::int64_t kBias = std::int64_t(1) << 31;

// Metropolis acceptance of an energy change at temperature T with the uniform deviate u.
bool metropolis(double delta, double T, double u) { return delta <= 0 || (T > 0 && u < std::exp(-delta / T)); }

// Site relative to the canonical origin (i >= 0) as one integer ordered like (i, j).
std::int64_t pack(int i, int j) { return (static_cast<std::int64_t>(i) << 32) + (j + kBias); }
LatticeVector unpack(std::int64_t code) {
    return {static_cast<int>(code >> 32), static_cast<int>((code & 0xffffffffLL) - kBias)};
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Box and clusters
// ---------------------------------------------------------------------------------------------

Box::Box(int L_) : L(L_) {
    if (L < 2) throw std::invalid_argument("box must be at least 2, got " + std::to_string(L));
    if (L > 30000) throw std::invalid_argument("box must be at most 30000, got " + std::to_string(L));
    neighbour.resize(6 * static_cast<std::size_t>(n_sites()));
    for (int s = 0; s < n_sites(); ++s)
        for (int d = 0; d < 6; ++d) {
            const LatticeVector c = coords(s);
            neighbour[6 * s + d] = index(c[0] + kLatticeNeighbours[d][0], c[1] + kLatticeNeighbours[d][1]);
        }
}

int Box::index(int i, int j) const { return floor_mod(i, L) + L * floor_mod(j, L); }

void ClusterWorkspace::resize(int n_sites) {
    mark.assign(n_sites, 0u);
    position.assign(n_sites, LatticeVector{0, 0});
    stamp = 1;
}

Cluster find_cluster(const Box& box, const std::vector<int>& occupied, int start, ClusterWorkspace& ws) {
    Cluster cl;
    ws.queue.clear();
    ws.queue.push_back(start);
    ws.mark[start] = ws.stamp;
    ws.position[start] = box.coords(start);
    for (std::size_t head = 0; head < ws.queue.size(); ++head) {
        const int s = ws.queue[head];
        const LatticeVector u = ws.position[s];
        cl.members.push_back(s);
        cl.unwrapped.push_back(u);
        for (int d = 0; d < 6; ++d) {
            const int t = box.next(s, d);
            if (occupied[t] < 0) continue;
            const LatticeVector v{u[0] + kLatticeNeighbours[d][0], u[1] + kLatticeNeighbours[d][1]};
            if (ws.mark[t] != ws.stamp) {
                ws.mark[t] = ws.stamp;
                ws.position[t] = v;
                ws.queue.push_back(t);
            } else if (ws.position[t] != v) {
                // Reached again by another path: the cluster wraps around the box.
                add_wrap(cl, v[0] - ws.position[t][0], v[1] - ws.position[t][1]);
            }
        }
    }
    return cl;
}

// (i, j) -> identity, R120 (-i-j, i), R240 (j, -i-j), mirror x -> -x (-i-j, j), and the
// mirrors M R120 = (j, i), M R240 = (i, -i-j). (R60 (i, j) -> (-j, i+j) sends a1 -> a2 and
// a2 -> a2 - a1, and yellow corners to red ones; M sends a1 -> -a1, a2 -> a2 - a1, and the
// yellow corners at 90, 210, 330 degrees to 90, 330, 210 degrees. tests/test_montecarlo.py
// checks both on Cartesian corner directions.)
LatticeVector d3_transform(int op, const LatticeVector& v) {
    const int i = v[0], j = v[1];
    switch (op) {
        case 0: return {i, j};
        case 1: return {-i - j, i};
        case 2: return {j, -i - j};
        case 3: return {-i - j, j};
        case 4: return {j, i};
        case 5: return {i, -i - j};
        default: throw std::invalid_argument("op must lie in [0, 6)");
    }
}

std::size_t ShapeKeyHash::operator()(const ShapeKey& key) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ULL ^ key.size();
    for (const std::int64_t v : key) {
        std::uint64_t z = static_cast<std::uint64_t>(v) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        h ^= z ^ (z >> 31);
    }
    return static_cast<std::size_t>(h);
}

ShapeKey finite_shape_key(const std::vector<LatticeVector>& sites, std::vector<LatticeVector>* canonical_sites) {
    const std::size_t n = sites.size();
    ShapeKey best, work(n);
    std::vector<LatticeVector> moved(n);
    for (int op = 0; op < 6; ++op) {
        LatticeVector lo{std::numeric_limits<int>::max(), std::numeric_limits<int>::max()};
        for (std::size_t k = 0; k < n; ++k) {
            moved[k] = d3_transform(op, sites[k]);
            if (moved[k] < lo) lo = moved[k];
        }
        for (std::size_t k = 0; k < n; ++k) work[k] = pack(moved[k][0] - lo[0], moved[k][1] - lo[1]);
        std::sort(work.begin(), work.end());
        if (op == 0 || work < best) best.swap(work), work.resize(n);
    }
    if (canonical_sites) {
        canonical_sites->resize(n);
        for (std::size_t k = 0; k < n; ++k) (*canonical_sites)[k] = unpack(best[k]);
    }
    return best;
}

ShapeKey wrapped_shape_key(const Cluster& cl, int L) {
    ShapeKey key{-cl.rank(), L, cl.a, cl.b, cl.c};
    key.insert(key.end(), cl.members.begin(), cl.members.end());
    std::sort(key.begin() + 5, key.end());
    return key;
}

Topology cluster_topology(const std::vector<LatticeVector>& sites, const Cluster& wrap) {
    switch (wrap.rank()) {
        case 0: return make_topology(sites, Periodicity::None, {}, false);
        case 1: {
            const LatticeVector axis = wrap.a ? LatticeVector{wrap.a, wrap.b} : LatticeVector{0, wrap.c};
            return make_topology(sites, Periodicity::Fiber, {axis, LatticeVector{0, 0}}, false);
        }
        default: return make_topology(sites, Periodicity::Bulk, {LatticeVector{wrap.a, wrap.b}, LatticeVector{0, wrap.c}}, false);
    }
}

// ---------------------------------------------------------------------------------------------
// MonteCarlo
// ---------------------------------------------------------------------------------------------

template <class Model>
MonteCarlo<Model>::MonteCarlo(const Model& model, double g, int L, int n, std::uint64_t seed,
                              const MonteCarloOptions& options)
    : model_(model), g_(g), box_(L), options_(options), rng_(seed) {
    if (!(g >= 0) || !std::isfinite(g)) throw std::invalid_argument("g must be non-negative and finite, got " + std::to_string(g));
    if (n < 1) throw std::invalid_argument("n must be at least 1, got " + std::to_string(n));
    if (static_cast<long>(n) >= static_cast<long>(L) * L)
        throw std::invalid_argument("n must be smaller than box^2 = " + std::to_string(L * L) +
                                    " (a move needs an empty site), got " + std::to_string(n));
    occupant_.assign(box_.n_sites(), -1);
    label_.assign(box_.n_sites(), -1);
    ws_.resize(box_.n_sites());
    ws_canonical_.resize(box_.n_sites());
    // Random initial placement, drawn with the chain's own generator.
    particles_.assign(n, -1);
    std::vector<LatticeVector> sites;
    for (int p = 0; p < n; ++p) {
        const int s = random_empty_site();
        occupant_[s] = p;
        sites.push_back(box_.coords(s));
    }
    place(sites);
}

template <class Model>
std::uint64_t MonteCarlo<Model>::uniform_index(std::uint64_t n) {
    const std::uint64_t threshold = (0 - n) % n;  // 2^64 mod n: reject the biased remainder
    for (;;) {
        const std::uint64_t r = rng_();
        if (r >= threshold) return r % n;
    }
}

template <class Model>
double MonteCarlo<Model>::uniform01() {
    return static_cast<double>(rng_() >> 11) * 0x1.0p-53;
}

template <class Model>
int MonteCarlo<Model>::random_empty_site() {
    for (;;) {
        const int s = static_cast<int>(uniform_index(box_.n_sites()));
        if (occupant_[s] < 0) return s;
    }
}

template <class Model>
int MonteCarlo<Model>::occupied_neighbours(int s) const {
    int count = 0;
    for (int d = 0; d < 6; ++d) count += occupant_[box_.next(s, d)] >= 0;
    return count;
}

template <class Model>
void MonteCarlo<Model>::place(const std::vector<LatticeVector>& sites) {
    if (static_cast<int>(sites.size()) != n())
        throw std::invalid_argument("sites: expected " + std::to_string(n()) + " sites, got " + std::to_string(sites.size()));
    std::vector<int> occupant(box_.n_sites(), -1), particles(sites.size());
    for (std::size_t p = 0; p < sites.size(); ++p) {
        const int s = box_.index(sites[p][0], sites[p][1]);
        if (occupant[s] >= 0)
            throw std::invalid_argument("sites: site (" + std::to_string(sites[p][0]) + ", " + std::to_string(sites[p][1]) +
                                        ") is occupied twice (modulo the box)");
        occupant[s] = static_cast<int>(p);
        particles[p] = s;
    }
    occupant_.swap(occupant);
    particles_.swap(particles);
    bonds_ = 0;
    for (const int s : particles_) bonds_ += occupied_neighbours(s);
    bonds_ /= 2;
    deformation_ = scratch_deformation(true, options_.cache, true);
}

template <class Model>
double MonteCarlo<Model>::shape_energy(const ShapeKey& key, const Cluster& cl) {
    std::vector<LatticeVector> sites;
    Cluster wrap;
    if (cl.rank() == 0) {
        sites.resize(key.size());
        for (std::size_t k = 0; k < key.size(); ++k) sites[k] = unpack(key[k]);
    } else {
        // Canonical embedding: the search from the smallest member site, sorted.
        ws_canonical_.new_round();
        wrap = find_cluster(box_, occupant_, static_cast<int>(key[5]), ws_canonical_);
        sites = wrap.unwrapped;
        std::sort(sites.begin(), sites.end());
    }
    return relaxed_cluster_energy(model_, cluster_topology(sites, wrap), options_.relax, counters.relax);
}

template <class Model>
double MonteCarlo<Model>::raw_energy(const Cluster& cl) {
    if (cl.rank() == 0 && cl.size() == 1) return 0.0;
    return relaxed_cluster_energy(model_, cluster_topology(cl.unwrapped, cl), options_.relax, counters.relax);
}

template <class Model>
double MonteCarlo<Model>::cluster_energy(const Cluster& cl) {
    if (cl.rank() == 0 && cl.size() == 1) return 0.0;  // an isolated particle takes its rest shape
    const ShapeKey key = cl.rank() ? wrapped_shape_key(cl, box_.L) : finite_shape_key(cl.unwrapped);
    if (!options_.cache) return shape_energy(key, cl);
    const auto it = cache_.find(key);
    if (it != cache_.end()) {
        ++counters.cache_hits;
        return it->second;
    }
    ++counters.cache_misses;
    const double e = shape_energy(key, cl);
    if (cache_entries_ + key.size() > options_.cache_limit) {
        clear_cache();
        ++counters.cache_clears;
    }
    cache_entries_ += key.size();
    cache_.emplace(key, e);
    return e;
}

template <class Model>
int MonteCarlo<Model>::new_cluster_id(double deformation) {
    if (free_ids_.empty()) {
        cluster_deformation_.push_back(deformation);
        return static_cast<int>(cluster_deformation_.size()) - 1;
    }
    const int id = free_ids_.back();
    free_ids_.pop_back();
    cluster_deformation_[id] = deformation;
    return id;
}

template <class Model>
double MonteCarlo<Model>::scratch_deformation(bool canonical, bool cached, bool relabel) {
    const bool saved = options_.cache;
    options_.cache = cached;
    if (relabel) cluster_deformation_.clear(), free_ids_.clear();
    ws_.new_round();
    double total = 0.0;
    try {
        for (const int s : particles_) {
            if (ws_.seen(s)) continue;
            const Cluster cl = find_cluster(box_, occupant_, s, ws_);
            const double e = canonical ? cluster_energy(cl) : raw_energy(cl);
            total += e;
            if (relabel) {
                const int id = new_cluster_id(e);
                for (const int m : cl.members) label_[m] = id;
            }
        }
    } catch (...) {
        options_.cache = saved;
        throw;
    }
    options_.cache = saved;
    return total;
}

template <class Model>
double MonteCarlo<Model>::box_energy(bool canonical) {
    return -g_ * static_cast<double>(bonds_) + scratch_deformation(canonical, false, false);
}

template <class Model>
bool MonteCarlo<Model>::step(double T) {
    ++counters.attempted;
    // No deviate is drawn without cluster moves, so particle-move chains keep their sequence.
    if (options_.cluster_moves > 0 && uniform01() < options_.cluster_moves) return cluster_step();
    return particle_step(T);
}

template <class Model>
bool MonteCarlo<Model>::cluster_step() {
    ++counters.cluster_attempted;
    const int a = particles_[uniform_index(particles_.size())];
    const int L = box_.L;
    const int di = static_cast<int>(uniform_index(L)), dj = static_cast<int>(uniform_index(L));
    if (di == 0 && dj == 0) return false;
    ws_.new_round();
    const Cluster cl = find_cluster(box_, occupant_, a, ws_);
    if (cl.rank() > 0) return false;  // a wrapped cluster is periodic: a shift changes nothing
    const int id = label_[a];
    std::vector<int> targets;
    targets.reserve(cl.members.size());
    for (const int m : cl.members) {
        const LatticeVector c = box_.coords(m);
        const int t = box_.index(c[0] + di, c[1] + dj);
        // The target and its neighbours must be empty or in the cluster itself (those sites are
        // vacated or re-filled by it): no overlap, no new contact, so no energy change. The
        // cluster's sites are the ones marked by the search just done.
        if (occupant_[t] >= 0 && !ws_.seen(t)) return false;
        for (int d = 0; d < 6; ++d) {
            const int u = box_.next(t, d);
            if (occupant_[u] >= 0 && !ws_.seen(u)) return false;
        }
        targets.push_back(t);
    }
    std::vector<int> moved(cl.members.size());
    for (std::size_t k = 0; k < cl.members.size(); ++k) {
        moved[k] = occupant_[cl.members[k]];
        occupant_[cl.members[k]] = -1;
        label_[cl.members[k]] = -1;
    }
    for (std::size_t k = 0; k < targets.size(); ++k) {
        occupant_[targets[k]] = moved[k];
        label_[targets[k]] = id;
        particles_[moved[k]] = targets[k];
    }
    ++counters.accepted;
    ++counters.cluster_accepted;
    return true;
}

template <class Model>
bool MonteCarlo<Model>::particle_step(double T) {
    const int p = static_cast<int>(uniform_index(particles_.size()));
    const int a = particles_[p];
    const int b = random_empty_site();

    const int lost = occupied_neighbours(a);  // bonds of the particle at a (b is empty)
    // The move, undone unless accepted.
    const auto undo = [&] {
        occupant_[b] = -1;
        occupant_[a] = p;
        particles_[p] = a;
    };
    occupant_[a] = -1;
    occupant_[b] = p;
    particles_[p] = b;
    const int gained = occupied_neighbours(b);  // bonds at b (a is now empty)
    // Delayed acceptance, first stage: the surrogate energy, without relaxation. Uniform
    // deviates are drawn whatever the energy change, so that roundoff in an energy can never
    // shift the random sequence.
    const double surrogate = options_.delayed_acceptance ? -(g_ - options_.bond_deformation) * (gained - lost) : 0.0;
    if (options_.delayed_acceptance && !metropolis(surrogate, T, uniform01())) {
        undo();
        ++counters.screened;
        return false;
    }
    double old_deformation = 0.0, new_deformation = 0.0;
    try {
        if (options_.incremental) {
            // Clusters before the move: the one left at a, and those next to b.
            old_ids_.assign(1, label_[a]);
            for (int d = 0; d < 6; ++d) {
                const int t = box_.next(b, d);
                if (occupant_[t] >= 0 && std::find(old_ids_.begin(), old_ids_.end(), label_[t]) == old_ids_.end())
                    old_ids_.push_back(label_[t]);
            }
            for (const int id : old_ids_) old_deformation += cluster_deformation_[id];
            // Clusters after it: the one at b (merging its neighbours), and the pieces left at a.
            fresh_.clear();
            fresh_energy_.clear();
            ws_.new_round();
            fresh_.push_back(find_cluster(box_, occupant_, b, ws_));
            for (int d = 0; d < 6; ++d) {
                const int t = box_.next(a, d);
                if (occupant_[t] >= 0 && !ws_.seen(t)) fresh_.push_back(find_cluster(box_, occupant_, t, ws_));
            }
            for (const Cluster& cl : fresh_) {
                fresh_energy_.push_back(cluster_energy(cl));
                new_deformation += fresh_energy_.back();
            }
        } else {
            old_deformation = deformation_;
            new_deformation = scratch_deformation(true, false, false);
        }
    } catch (...) {
        undo();
        throw;
    }
    // Metropolis on dE (or, second stage, on dE - dE_s).
    const double delta = -g_ * (gained - lost) + (new_deformation - old_deformation) - surrogate;
    if (!metropolis(delta, T, uniform01())) {
        undo();
        return false;
    }
    ++counters.accepted;
    bonds_ += gained - lost;
    if (!options_.incremental) {
        deformation_ = new_deformation;
        return true;
    }
    deformation_ += new_deformation - old_deformation;
    for (const int id : old_ids_) free_ids_.push_back(id);
    for (std::size_t k = 0; k < fresh_.size(); ++k) {
        const int id = new_cluster_id(fresh_energy_[k]);
        for (const int m : fresh_[k].members) label_[m] = id;
    }
    return true;
}

template <class Model>
std::int64_t MonteCarlo<Model>::run(double T, std::int64_t steps) {
    if (!(T >= 0) || !std::isfinite(T)) throw std::invalid_argument("T must be non-negative and finite, got " + std::to_string(T));
    std::int64_t accepted = 0;
    for (std::int64_t k = 0; k < steps; ++k) accepted += step(T);
    return accepted;
}

template <class Model>
std::string MonteCarlo<Model>::rng_state() const {
    std::ostringstream out;
    out << rng_;
    return out.str();
}

template <class Model>
void MonteCarlo<Model>::set_rng_state(const std::string& state) {
    std::istringstream in(state);
    std::mt19937_64 r;
    in >> r;
    if (in.fail()) throw std::invalid_argument("rng_state: not a std::mt19937_64 state");
    rng_ = r;
}

template class MonteCarlo<HexagonModel>;

}  // namespace pyfrustrate
