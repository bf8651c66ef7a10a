// Relaxing a cluster that differs from an already relaxed one (its parent) by a particle or a
// few, from the parent's relaxed state and with the parent's Hessian factor, modified instead of
// made anew (issue 32, item 3).
//
// Each particle's energy depends on its own corners only, so the Hessian of the child at the
// parent's state is the parent's Hessian minus the blocks of the particles that left plus those
// of the particles that joined: rows deleted (corners no particle holds any more), rows added
// (new corners), and a low-rank update and downdate (the shared corners of the particles that
// came or went), each a CHOLMOD Modify call on the parent's LDL^T (cholesky.hpp,
// ModifiableFactor). No Hessian pattern, symbolic analysis or numeric factorisation of the child
// is made. The child then takes chord steps, -M^-1 g with that fixed matrix M, each with the
// backtracking line search of newton_from, to the same force tolerance as a fresh relaxation:
// the energy is exact to that tolerance whatever the matrix, which only decides how fast the
// force falls. Where it falls too slowly (the matrix has drifted from the Hessian over many
// generations) the exact Hessian is factorised anew at the current state; where the modified
// matrix is not positive definite, the relaxation is made fresh (relax_newton).
//
// Periodic cells (fibres, bulks) are always relaxed fresh: their period parameters couple every
// image slot. The Monte Carlo warm-starts its wrapping clusters instead (montecarlo/chain.hpp).
#pragma once

#include "relax.hpp"

#include <map>
#include <memory>
#include <string>

namespace pyfrustrate {

// What a relaxed finite cluster hands on to the clusters made from it.
struct RelaxedCluster {
    Topology topology;
    Vector displacement;           // the relaxed displacement (rigid motion not removed)
    Vector factor_state;           // the displacement at which the factor's matrix is the exact Hessian
    std::vector<int> pins;         // the pinned degrees of freedom
    std::vector<int> row_of_dof;   // each degree of freedom's row in the factor, -1 if pinned
    std::shared_ptr<const ModifiableFactor> factor;
    // Per particle: its block in the factor's matrix is |h| (the Hessian with its eigenvalues'
    // signs dropped) rather than h itself; see modified_cluster.
    std::vector<char> absolute_block;
    long fresh_nonzeros = 0;       // nnz(L) when last factorised from scratch
    int modifications = 0;         // particles added or removed since then
};

// How a relaxation from a parent went (counted by the callers: benchmarks, Monte Carlo, tests).
struct ParentRelaxStats {
    bool from_parent = false;   // the parent's factor was modified and used
    int chord_steps = 0;        // steps taken with the modified (or refreshed) factor
    int refactorizations = 0;   // fresh factorisations of the exact Hessian along the way
    std::string fresh_reason;   // why the relaxation was made fresh instead ("" if it was not)
};

// Rows a factor carries beyond its degrees of freedom, for corners of particles that join later
// (a hexagon brings at most 6 new corners, 12 rows): refactorised when they run out.
constexpr int kSpareRows = 48;
// Refactorise from scratch once nnz(L) has grown by this factor through modifications, or after
// this many particles changed: the matrix drifts from the Hessian of the current state.
constexpr double kFillGrowthLimit = 1.5;
constexpr int kModificationLimit = 64;
// A chord step must divide the largest force by at least this much, else the exact Hessian is
// factorised anew at the current state.
constexpr double kChordContraction = 0.7;
// At most this many particles changed between parent and child.
constexpr int kMaxChangedParticles = 4;
constexpr const char* kNotPositiveDefinite = "the modified matrix is not positive definite";

// Particle p's Hessian in the lab frame, with respect to its corners' displacements (finite
// topologies: no period images).
template <class Model>
Eigen::Matrix<double, 2 * Model::kCornerCount, 2 * Model::kCornerCount> particle_hessian(const Network<Model>& net,
                                                                                        const Vector& u, int p) {
    const PeriodMap map = net.period_map(u);
    typename Model::Hessian h = Model::Hessian::Zero();
    net.model.energy_of_displacement(net.local_displacements(u, map, p), nullptr, &h);
    Network<Model>::turn(net.frame(p), h);
    return h;
}

// The exact Hessian at u factorised with spare rows: a cluster ready to hand on. nullptr where
// the Hessian is not positive definite there.
template <class Model>
std::shared_ptr<RelaxedCluster> factorised_cluster(const Model& model, const Topology& topology, const Vector& u,
                                                   const Vector& relaxed) {
    auto out = std::make_shared<RelaxedCluster>();
    out->topology = topology;
    out->pins = rigid_body_pins(topology);
    const Network<Model> net{model, out->topology};
    const HessianPattern pat = net.hessian_pattern(out->pins);
    std::vector<int> rows;
    auto factor = ModifiableFactor::make(pat.n_free, pat.column_start, pat.row, net.hessian(u, pat, /*exact=*/true),
                                         kSpareRows, rows);
    if (!factor) return nullptr;
    out->row_of_dof.assign(pat.free_index.size(), -1);
    for (size_t d = 0; d < pat.free_index.size(); ++d)
        if (pat.free_index[d] >= 0) out->row_of_dof[d] = rows[pat.free_index[d]];
    out->fresh_nonzeros = factor->nonzeros();
    out->factor = std::move(factor);
    out->factor_state = u;
    out->displacement = relaxed;
    out->absolute_block.assign(topology.n_particles(), 0);
    return out;
}

// `cluster` moved rigidly by `shift` (cells): the same factor, displacements and pins, its sites
// and reference corners translated (a finite cluster's energy and Hessian do not change under a
// translation). The Monte Carlo's rigid cluster moves carry a cluster's factor to new sites
// (montecarlo/chain.hpp, translate_factors); its children, found there, match it particle by
// particle only if its sites moved with it.
inline std::shared_ptr<RelaxedCluster> translated_cluster(const RelaxedCluster& cluster, const LatticeVector& shift) {
    auto out = std::make_shared<RelaxedCluster>(cluster);
    for (Site& s : out->topology.sites) s[0] += shift[0], s[1] += shift[1];
    const Vec2 d = cell_position(shift);
    for (Vec2& r : out->topology.reference) r += d;
    out->topology.pivot += d;
    return out;
}

// Particle p's corners without a known displacement (known[c] == 0) placed by the rigid motion
// of its reference corners that best fits its corners with one (known[c] != 0; least squares,
// the translation alone if one is known); each placed corner is marked known[c] = 2 and, if
// new_dof is given, its two degrees of freedom appended to it. Returns the largest distance of a
// corner with known[c] == 1 from that fit (0 if p has no known corner, and then nothing is
// placed): a particle that bridges corners its neighbours left far apart starts under a large
// strain. The one rigid fit of a joining particle, for the parent's factor (below) and the Monte
// Carlo's warm starts (montecarlo/chain.hpp).
inline double fit_particle_corners(const Topology& topology, int p, Vector& u, std::vector<int>& known,
                                   std::vector<int>* new_dof = nullptr) {
    const int C = topology.tiling().corners;
    Vec2 r_mean = Vec2::Zero(), x_mean = Vec2::Zero();
    int n = 0;
    for (int s = 0; s < C; ++s) {
        const int c = topology.corner[p][s];
        if (!known[c]) continue;
        r_mean += topology.reference[c];
        x_mean += topology.reference[c] + u.segment<2>(2 * c);
        ++n;
    }
    if (n == 0) return 0.0;
    r_mean /= n, x_mean /= n;
    double sin_sum = 0, cos_sum = 0;
    for (int s = 0; s < C; ++s) {
        const int c = topology.corner[p][s];
        if (!known[c]) continue;
        const Vec2 r = topology.reference[c] - r_mean, x = topology.reference[c] + u.segment<2>(2 * c) - x_mean;
        sin_sum += r.x() * x.y() - r.y() * x.x();
        cos_sum += r.dot(x);
    }
    const double angle = n > 1 ? std::atan2(sin_sum, cos_sum) : 0.0;
    Mat2 rotation;
    rotation << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
    double misfit = 0;
    for (int s = 0; s < C; ++s) {
        const int c = topology.corner[p][s];
        const Vec2 fit = x_mean + rotation * (topology.reference[c] - r_mean) - topology.reference[c];
        if (known[c] == 1) {
            misfit = std::max(misfit, (fit - u.segment<2>(2 * c)).norm());
        } else if (!known[c]) {
            u.segment<2>(2 * c) = fit;
            known[c] = 2;
            if (new_dof) new_dof->push_back(2 * c), new_dof->push_back(2 * c + 1);
        }
    }
    return misfit;
}

// The corners of particles without a known displacement (known[c] == 0) placed by
// fit_particle_corners, particle by particle (a corner placed for one particle counts in the
// fits of later ones, not in their misfit); known is 0/1 again afterwards. Returns the largest
// misfit.
inline double place_unknown_corners(const Topology& topology, Vector& u, std::vector<int>& known) {
    double misfit = 0;
    const int C = topology.tiling().corners;
    for (int p = 0; p < topology.n_particles(); ++p) {
        bool has_unknown = false;
        for (int s = 0; s < C; ++s) has_unknown = has_unknown || !known[topology.corner[p][s]];
        if (has_unknown) misfit = std::max(misfit, fit_particle_corners(topology, p, u, known));
    }
    for (int& k : known) k = k ? 1 : 0;
    return misfit;
}

// The corners only particles that joined hold (dof: their degrees of freedom), relaxed with
// every other corner held: damped Newton on the joining particles' energy, a dense problem of at
// most 12 unknowns per particle. The rigid fit leaves a joining particle strained: on disks its
// exact Hessian had an eigenvalue far below the network's stiffness and the start's energy was
// well above the child's minimum; relaxed this way, the start is close to the minimum, the
// matrix positive definite, and the chord steps converge in a few steps (bench_parent_relax).
template <class Model>
void relax_new_corners(const Network<Model>& net, Vector& u, const std::vector<int>& particles,
                       const std::vector<int>& dof, double tolerance) {
    constexpr int C = Model::kCornerCount;
    const int n = static_cast<int>(dof.size());
    if (n == 0) return;
    std::vector<int> index_of(u.size(), -1);
    for (int i = 0; i < n; ++i) index_of[dof[i]] = i;
    const PeriodMap map = net.period_map(u);
    auto evaluate = [&](const Vector& v, Vector* gradient, Eigen::MatrixXd* hessian) {
        double e = 0;
        if (gradient) gradient->setZero(n);
        if (hessian) hessian->setZero(n, n);
        for (const int p : particles) {
            typename Model::Corners f = Model::Corners::Zero();
            typename Model::Hessian h = Model::Hessian::Zero();
            e += net.model.energy_of_displacement(net.local_displacements(v, map, p), gradient ? &f : nullptr,
                                                  hessian ? &h : nullptr);
            Network<Model>::turn(net.frame(p), f, false);
            if (hessian) Network<Model>::turn(net.frame(p), h);
            for (int a = 0; a < 2 * C; ++a) {
                const int i = index_of[2 * net.topology.corner[p][a / 2] + a % 2];
                if (i < 0) continue;
                if (gradient) (*gradient)[i] += f[a];
                if (hessian)
                    for (int b = 0; b < 2 * C; ++b) {
                        const int j = index_of[2 * net.topology.corner[p][b / 2] + b % 2];
                        if (j >= 0) (*hessian)(i, j) += h(a, b);
                    }
            }
        }
        return e;
    };
    Vector g;
    Eigen::MatrixXd h;
    double e = evaluate(u, &g, &h), shift = 0;
    for (int iteration = 0; iteration < 50 && max_abs(g) > tolerance; ++iteration) {
        Eigen::LDLT<Eigen::MatrixXd> ldlt;
        Vector step;
        for (int attempt = 0; attempt < 30; ++attempt) {
            Eigen::MatrixXd damped = h;
            damped.diagonal() *= 1 + shift;
            ldlt.compute(damped);
            if (ldlt.info() == Eigen::Success && ldlt.isPositive() && (ldlt.vectorD().array() > 0).all()) {
                step = -ldlt.solve(g);
                break;
            }
            shift = shift > 0 ? 10 * shift : 1e-4;
        }
        if (step.size() == 0) return;
        const double longest = max_abs(step);
        if (longest > 0.25) step *= 0.25 / longest;
        double length = 1;
        Vector trial = u;
        bool accepted = false;
        for (int halving = 0; halving < 30; ++halving, length *= 0.5) {
            trial = u;
            for (int i = 0; i < n; ++i) trial[dof[i]] += length * step[i];
            const double te = evaluate(trial, nullptr, nullptr);
            if (std::isfinite(te) && te <= e + 1e-4 * length * g.dot(step)) {
                accepted = true;
                break;
            }
        }
        if (!accepted) return;
        u = std::move(trial);
        e = evaluate(u, &g, &h);
        shift = shift > 1e-6 ? shift / 100 : 0;
    }
}

// Chord steps -M^-1 g from u with the cluster's factor M (rows of cluster.row_of_dof), each with
// newton_from's backtracking line search and trust region, until the largest force is below
// the tolerance; when a step contracts the force by less than kChordContraction, the exact
// Hessian at the current state replaces M (cluster is updated). Returns the result; unconverged
// with status "chord" + reason if M could not be refreshed (not positive definite).
template <class Model>
MinimizeResult chord_relax(const Model& model, std::shared_ptr<RelaxedCluster>& cluster, Vector u,
                           const MinimizeOptions& options, ParentRelaxStats& stats, int evaluations_before = 0) {
    const std::shared_ptr<RelaxedCluster> first = cluster;  // keeps `topology` alive when cluster is refreshed
    const Topology& topology = first->topology;
    const Network<Model> net{model, topology};
    Vector gradient;
    double energy = net.energy(u, &gradient);
    for (const int d : cluster->pins) gradient[d] = 0;
    double gnorm = max_abs(gradient);
    int evaluations = evaluations_before + 1, steps = 0, factorizations = 0;
    std::string stop;
    bool failed = false;
    while (gnorm > options.gradient_tolerance) {
        if (evaluations >= options.max_iterations) {
            stop = "maximum number of iterations reached";
            break;
        }
        Vector rhs = Vector::Zero(cluster->factor->rows());
        for (int d = 0; d < u.size(); ++d)
            if (cluster->row_of_dof[d] >= 0) rhs[cluster->row_of_dof[d]] = gradient[d];
        const Vector solved = cluster->factor->solve(rhs);
        Vector direction(u.size());
        for (int d = 0; d < u.size(); ++d) direction[d] = cluster->row_of_dof[d] >= 0 ? -solved[cluster->row_of_dof[d]] : 0.0;
        if (!direction.allFinite() || !(gradient.dot(direction) < 0)) {
            stop = "the modified matrix gives no descent direction";
            failed = true;
            break;
        }
        LineSearchPoint next;
        const bool accepted =
            backtracking_step(net, u, direction, gradient, energy, gnorm, options, evaluations, cluster->pins, next);
        if (!accepted) {
            stop = evaluations >= options.max_iterations ? "maximum number of iterations reached"
                                                         : "round-off floor: no step lowers the energy or the largest force";
            break;
        }
        ++steps;
        ++stats.chord_steps;
        const double previous_gnorm = gnorm;
        u = std::move(next.u);
        energy = next.energy;
        gradient = std::move(next.gradient);
        gnorm = next.gnorm;
        if (gnorm > options.gradient_tolerance && gnorm > kChordContraction * previous_gnorm) {
            // The matrix has drifted from the Hessian: the exact one at this state instead.
            auto fresh = factorised_cluster(model, topology, u, u);
            ++factorizations;
            if (!fresh) {
                stop = "the exact Hessian is not positive definite";
                failed = true;
                break;
            }
            ++stats.refactorizations;
            cluster = std::move(fresh);
        }
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
    result.handed_over = failed;
    return result;
}

// The child's factor: a copy of the parent's, modified for the particles that left and joined
// (rows deleted and added, the shared corners' blocks updated and downdated), and the child's
// start (the parent's relaxed displacement on shared corners, new corners by a rigid fit).
// nullptr and a reason where the parent cannot serve.
template <class Model>
std::shared_ptr<RelaxedCluster> modified_cluster(const Model& model, const Topology& child, const RelaxedCluster& parent,
                                                 double tolerance, Vector& start, std::string& reason,
                                                 bool absolute_blocks = false) {
    constexpr int C = Model::kCornerCount;
    const Topology& pt = parent.topology;
    if (child.periodicity != Periodicity::None || pt.periodicity != Periodicity::None) {
        reason = "periodic cell";
        return nullptr;
    }
    if (child.tiling_kind != pt.tiling_kind) {
        reason = "another tiling";
        return nullptr;
    }
    if (parent.modifications >= kModificationLimit || parent.factor->nonzeros() > kFillGrowthLimit * parent.fresh_nonzeros) {
        reason = "the parent's factor has drifted (modifications or fill)";
        return nullptr;
    }
    // Particles matched by site; corners through the slots of matched particles.
    const SiteLookup parent_particle(pt.sites, pt.tiling().sublattices);
    const int nc = child.n_corners();
    std::vector<int> parent_corner(nc, -1), child_corner(pt.n_corners(), -1);
    std::vector<int> added;
    std::vector<char> kept(pt.n_particles(), 0), absolute(child.n_particles(), absolute_blocks);
    for (int p = 0; p < child.n_particles(); ++p) {
        const int match = parent_particle(child.sites[p]);
        if (match < 0) {
            added.push_back(p);
            continue;
        }
        kept[match] = 1;
        absolute[p] = parent.absolute_block[match];
        for (int s = 0; s < C; ++s) {
            const int c = child.corner[p][s], q = pt.corner[match][s];
            if ((parent_corner[c] >= 0 && parent_corner[c] != q) || (child_corner[q] >= 0 && child_corner[q] != c)) {
                reason = "corners joined or split otherwise than by the particles that changed";
                return nullptr;
            }
            parent_corner[c] = q, child_corner[q] = c;
        }
    }
    std::vector<int> removed;
    for (int q = 0; q < pt.n_particles(); ++q)
        if (!kept[q]) removed.push_back(q);
    if (added.size() + removed.size() > static_cast<size_t>(kMaxChangedParticles)) {
        reason = "more than " + std::to_string(kMaxChangedParticles) + " particles changed";
        return nullptr;
    }
    if (added.size() == 0 && removed.empty()) {
        reason = "";
    }
    auto out = std::make_shared<RelaxedCluster>();
    out->topology = child;
    out->fresh_nonzeros = parent.fresh_nonzeros;
    out->modifications = parent.modifications + static_cast<int>(added.size() + removed.size());
    for (const int d : parent.pins) {
        const int c = child_corner[d / 2];
        if (c < 0) {
            reason = "a pinned corner left";
            return nullptr;
        }
        out->pins.push_back(2 * c + d % 2);
    }
    auto factor = parent.factor->copy();
    // Rows of the parent's corners that no particle of the child holds leave the matrix.
    for (int q = 0; q < pt.n_corners(); ++q)
        if (child_corner[q] < 0)
            for (int k = 0; k < 2; ++k)
                if (parent.row_of_dof[2 * q + k] >= 0 && !factor->delete_row(parent.row_of_dof[2 * q + k])) {
                    reason = "row deletion failed";
                    return nullptr;
                }
    out->row_of_dof.assign(2 * nc, -1);
    start = Vector::Zero(2 * nc);
    out->factor_state = Vector::Zero(2 * nc);
    std::vector<int> known(nc, 0);
    for (int c = 0; c < nc; ++c)
        if (parent_corner[c] >= 0) {
            known[c] = 1;
            for (int k = 0; k < 2; ++k) {
                out->row_of_dof[2 * c + k] = parent.row_of_dof[2 * parent_corner[c] + k];
                start[2 * c + k] = parent.displacement[2 * parent_corner[c] + k];
                out->factor_state[2 * c + k] = parent.factor_state[2 * parent_corner[c] + k];
            }
        }
    for (const int d : out->pins) out->row_of_dof[d] = -1;
    place_unknown_corners(child, start, known);
    const Network<Model> child_net{model, child}, parent_net{model, pt};
    {
        std::vector<int> new_dof;
        for (int c = 0; c < nc; ++c)
            if (parent_corner[c] < 0 && std::find(out->pins.begin(), out->pins.end(), 2 * c) == out->pins.end())
                new_dof.push_back(2 * c), new_dof.push_back(2 * c + 1);
        relax_new_corners(child_net, start, added, new_dof, 1e-3 * tolerance);
    }
    for (int c = 0; c < nc; ++c)
        if (parent_corner[c] < 0) out->factor_state.segment<2>(2 * c) = start.segment<2>(2 * c);
    // The blocks to add (particles that joined, at the start) and subtract (particles that left,
    // at the state the parent's matrix holds), summed on the rows they touch that stay.
    std::vector<std::tuple<int, int, int, double>> entries;  // (changed particle, row, row, value)
    std::vector<int> new_rows;  // rows of corners new in the child, taken from the identity rows
    for (int c = 0; c < nc; ++c)
        if (parent_corner[c] < 0)
            for (int k = 0; k < 2; ++k) {
                if (out->row_of_dof[2 * c + k] == -1 &&
                    std::find(out->pins.begin(), out->pins.end(), 2 * c + k) == out->pins.end()) {
                    const int r = factor->take_free_row();
                    if (r < 0) {
                        reason = "no spare rows left";
                        return nullptr;
                    }
                    out->row_of_dof[2 * c + k] = r;
                    new_rows.push_back(r);
                }
            }
    std::vector<char> is_new(factor->rows(), 0);
    for (const int r : new_rows) is_new[r] = 1;
    // A particle that joins enters with its exact Hessian h at the start (its new corners relaxed
    // above); where that leaves the matrix indefinite, the caller asks again with
    // absolute_blocks, and it enters with |h|, h with the signs of its eigenvalues dropped:
    // positive semidefinite, the rigid motions its only null space, blocked by the two or more
    // corners it shares. The chord steps' line search and force tolerance keep the result exact
    // either way; a particle's flag says which block to take out when it leaves.
    auto collect = [&](int tag, const Network<Model>& net, const Vector& u, int p, const std::vector<int>& rows_of,
                       double sign, bool use_absolute) {
        auto h = particle_hessian(net, u, p);
        if (use_absolute) {
            const Eigen::SelfAdjointEigenSolver<decltype(h)> eig(h);
            h = eig.eigenvectors() * eig.eigenvalues().cwiseAbs().asDiagonal() * eig.eigenvectors().transpose();
        }
        for (int a = 0; a < 2 * C; ++a)
            for (int b = 0; b < 2 * C; ++b) {
                const int ra = rows_of[2 * net.topology.corner[p][a / 2] + a % 2];
                const int rb = rows_of[2 * net.topology.corner[p][b / 2] + b % 2];
                if (ra >= 0 && rb >= 0) entries.emplace_back(tag, ra, rb, sign * h(a, b));
            }
    };
    // Rows of the parent's dof that stay in the child (the others were deleted above).
    std::vector<int> parent_rows_kept(parent.row_of_dof.size(), -1);
    for (int q = 0; q < pt.n_corners(); ++q)
        if (child_corner[q] >= 0)
            for (int k = 0; k < 2; ++k) parent_rows_kept[2 * q + k] = parent.row_of_dof[2 * q + k];
    int tags = 0;
    for (const int q : removed)
        collect(tags++, parent_net, parent.factor_state, q, parent_rows_kept, -1.0, parent.absolute_block[q]);
    for (const int p : added) collect(tags++, child_net, out->factor_state, p, out->row_of_dof, 1.0, absolute_blocks);
    // New rows: their whole column (they had no entries before); old rows: a symmetric change,
    // one block per changed particle. Each block = V diag(lambda) V^T: the positive part an
    // update, the negative part a downdate (after the rows are added, so that no intermediate
    // matrix loses definiteness needlessly). One block per particle, not one for all: a column
    // of V spanning two particles far apart would join their paths in the elimination tree, and
    // the update would fill L along both (a surface move grew nnz(L) several times as much).
    std::map<int, std::vector<std::pair<int, double>>> new_columns;
    struct Block {
        std::vector<int> rows;
        std::map<int, int> index;
        Eigen::MatrixXd up, down;
    };
    std::vector<Block> blocks(tags);
    for (const auto& [tag, ra, rb, v] : entries) {
        if (is_new[rb]) {
            new_columns[rb].emplace_back(ra, v);
        } else if (!is_new[ra]) {
            for (const int r : {ra, rb})
                if (blocks[tag].index.emplace(r, static_cast<int>(blocks[tag].rows.size())).second)
                    blocks[tag].rows.push_back(r);
        }
    }
    std::vector<Eigen::MatrixXd> changes(tags);
    for (int t = 0; t < tags; ++t) changes[t] = Eigen::MatrixXd::Zero(blocks[t].rows.size(), blocks[t].rows.size());
    for (const auto& [tag, ra, rb, v] : entries)
        if (!is_new[ra] && !is_new[rb]) changes[tag](blocks[tag].index.at(ra), blocks[tag].index.at(rb)) += v;
    for (int t = 0; t < tags; ++t) {
        const Eigen::MatrixXd& change = changes[t];
        if (change.size() == 0) continue;
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(change);
        const double scale = eig.eigenvalues().cwiseAbs().maxCoeff();
        std::vector<int> positive, negative;
        for (int i = 0; i < change.rows(); ++i) {
            const double l = eig.eigenvalues()[i];
            if (l > 1e-14 * scale) positive.push_back(i);
            if (l < -1e-14 * scale) negative.push_back(i);
        }
        Block& block = blocks[t];
        block.up.resize(change.rows(), positive.size());
        block.down.resize(change.rows(), negative.size());
        for (size_t i = 0; i < positive.size(); ++i)
            block.up.col(i) = eig.eigenvectors().col(positive[i]) * std::sqrt(eig.eigenvalues()[positive[i]]);
        for (size_t i = 0; i < negative.size(); ++i)
            block.down.col(i) = eig.eigenvectors().col(negative[i]) * std::sqrt(-eig.eigenvalues()[negative[i]]);
    }
    for (const Block& block : blocks)
        if (!factor->update(block.rows, block.up, true)) {
            reason = "the update failed";
            return nullptr;
        }
    // New rows in order: each column holds its entries in rows in use (old rows, new rows added
    // before it) and its diagonal.
    std::vector<char> added_row(factor->rows(), 0);
    for (const int r : new_rows) {
        std::vector<std::pair<int, double>> column;
        for (const auto& [ra, v] : new_columns[r])
            if (!is_new[ra] || added_row[ra] || ra == r) column.emplace_back(ra, v);
        if (!factor->add_row(r, std::move(column))) {
            reason = "a row addition failed";
            return nullptr;
        }
        added_row[r] = 1;
    }
    for (const Block& block : blocks)
        if (!factor->update(block.rows, block.down, false)) {
            reason = "the downdate failed";
            return nullptr;
        }
    if (!factor->positive_definite()) {
        reason = kNotPositiveDefinite;
        return nullptr;
    }
    out->factor = std::move(factor);
    out->absolute_block = std::move(absolute);
    return out;
}

}  // namespace pyfrustrate
