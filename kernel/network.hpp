// A network: a topology with one particle model on every site. Its energy is the sum of the
// particle energies of the corners each particle sees (main text Eq. 15 for the aggregate
// energy at fixed topology); the loop over particles and the period map are written once here
// for every particle model.
//
// The particle contract: what Network, the minimisers, the linear solve and the Monte Carlo
// ask of a particle model (HexagonModel, RandomHexagonModel, TriangleModel), a small stateless
// value:
//   static constexpr TilingKind kTiling;        the tiling its topologies use (tiling.hpp)
//   static constexpr int kCornerCount;          its corners, checked below against the tiling's
//   static constexpr PointGroup kPointGroup;    its own symmetry (C3, D3), in its own frame: the
//                                               Monte Carlo keys shapes with it (shape_key.hpp)
//   using Corners, Hessian;                     CornerArray<kCornerCount>, CornerMatrix<...>
//   static Corners rest_corners();              rest shape without mismatch, own frame, about its
//                                               site centre (the tiling's slot offsets agree)
//   double energy_of_displacement(disp, Corners* grad, Hessian* hess) const;
//                                               energy of corners displaced by disp from
//                                               rest_corners, gradient and Hessian on request
//   Model without_mismatch() const;             eps = 0: its Hessian at rest is the stiffness of
//                                               the linear solve
//   double step_scale() const;                  typical corner displacement (the mismatch)
// Optional: energy_lanes<kLanes> and an overload of vectorised_finite_energy (hexagon.hpp).
// tests/test_particle_contract.py checks every model against it.
//
// Frames. A particle's rest shape is the model's, turned by its sublattice's frame (tiling.hpp;
// the down triangles of the triangle tiling are the up ones turned by 180 degrees): the model
// sees its corners' displacements turned back into its own frame, and its forces and stiffness
// are turned out again.
//
// Degrees of freedom. The public state is x = (corner 0 (x, y), corner 1 (x, y), ..., period-map
// parameters); the network works on the displacement u = x - x_ref from the bulk reference
// (Topology::reference_state). A particle is evaluated in its own frame from the displacements
// of its corners (and of their periodic images) from its rest shape, which the model keeps apart
// from that shape (Model::energy_of_displacement, elements.hpp). No coordinate of the size of the
// aggregate enters a force, and no stretch is formed as a difference of numbers of size 1, so
// the forces keep their digits at R = 100, a fibre of width 1000 or eps = 1e-8.
//
// The period map sends a corner of the cell to its image n:
//   fibre, straight:  r + n t
//   fibre, curved:    g^n(r) with g(r) = R(theta) (r - c) + c + t (a rigid motion about the
//                     cell's centroid c, so the fibre bends with constant curvature; theta is free)
//   bulk:             r + n1 t1 + n2 t2
#pragma once

#include "topology.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace pyfrustrate {

using Vector = Eigen::VectorXd;
using Mat2 = Eigen::Matrix2d;
constexpr int kMaxPeriodParameters = 4;
using PeriodJacobian = Eigen::Matrix<double, 2, kMaxPeriodParameters>;

// The period map at one state, in displacement form: the image n of a corner with reference
// position r_ref and displacement u is displaced from its reference image r_ref + n t_ref by
//   translations:  u + n1 dt1 + n2 dt2
//   curved fibre:  (R(n theta) - 1)(r_ref - c) + R(n theta) u + n dt + sum_a sigma (R(a theta) - 1) t
// where the sum runs over the rotations the n steps compose (a = 0..n-1, sigma = +1 for n > 0;
// a = -1..n, sigma = -1 for n < 0) and R - 1 is evaluated without cancellation (cos - 1 =
// -2 sin^2). Everything that depends on n only is computed once per state here.
class PeriodMap {
   public:
    // image_range: the largest |n| asked for (at least the topology's own max_image).
    PeriodMap(const Topology& t, const double* period_displacement, int image_range = 0)
        : t_(t), range_(std::max(image_range, t.max_image)) {
        if (t.periodicity == Periodicity::None) return;
        dt_[0] = Vec2(period_displacement[0], period_displacement[1]);
        if (t.periodicity == Periodicity::Bulk) dt_[1] = Vec2(period_displacement[2], period_displacement[3]);
        if (!t.curved) return;
        const Vec2 period = t.reference_period_parameters().head<2>() + dt_[0];
        theta_ = period_displacement[2] / t.bend_scale;
        steps_.resize(2 * range_ + 1);
        for (int n = -range_; n <= range_; ++n) {
            Step& st = steps_[n + range_];
            st.rotation = rotation(n * theta_);
            st.rotation_minus_one = rotation_minus_one(n * theta_);
            st.shift = n * dt_[0];
            st.d_shift.setZero();
            st.d_theta.setZero();
            st.dd_theta.setZero();
            st.dd_theta_shift.setZero();
            const int sigma = n > 0 ? 1 : -1;
            for (int m = 0; m < std::abs(n); ++m) {
                const int a = n > 0 ? m : -(m + 1);
                const Mat2 ra = rotation(a * theta_);
                st.shift += sigma * (rotation_minus_one(a * theta_) * period);
                st.d_shift += sigma * ra;
                st.d_theta += sigma * a * (ra * quarter() * period);
                st.dd_theta -= sigma * a * a * (ra * period);
                st.dd_theta_shift += sigma * a * (ra * quarter());
            }
        }
    }

    bool translation_only() const { return !t_.curved; }

    // Displacement of image n of a corner (reference r_ref, displacement u) from its reference image.
    Vec2 displacement(const LatticeVector& n, const Vec2& r_ref, const Vec2& u) const {
        if (n[0] == 0 && n[1] == 0) return u;
        if (!t_.curved) return u + n[0] * dt_[0] + n[1] * dt_[1];
        const Step& st = step(n[0]);
        return st.rotation_minus_one * (r_ref - t_.pivot) + st.rotation * u + st.shift;
    }

    // First derivatives of that image position: d/du (2x2) and d/d(period parameters) (2 x np).
    void jacobian(const LatticeVector& n, const Vec2& r_ref, const Vec2& u, Mat2& d_corner,
                  PeriodJacobian& d_period) const {
        d_period.setZero();
        if (!t_.curved) {
            d_corner.setIdentity();
            d_period.block<2, 2>(0, 0).diagonal().setConstant(n[0]);
            if (t_.periodicity == Periodicity::Bulk) d_period.block<2, 2>(0, 2).diagonal().setConstant(n[1]);
            return;
        }
        const Step& st = step(n[0]);
        d_corner = st.rotation;
        d_period.block<2, 2>(0, 0) = st.d_shift;
        d_period.col(2) = (n[0] * (st.rotation * quarter() * (r_ref - t_.pivot + u)) + st.d_theta) / t_.bend_scale;
    }

    // Curvature of the map contracted with a force f = de/d(image position): the second
    // derivatives f . d2pos / dq dq' that the exact Hessian adds to J^T h J. Only the bend
    // angle enters nonlinearly: d2/dtheta2, d2/dtheta du, d2/dtheta dt (zero for translations).
    // Writes the row of d2/d(bend) d(u_x, u_y, t_x, t_y) into mixed and d2/d(bend)^2 into pure.
    void curvature(const LatticeVector& n, const Vec2& r_ref, const Vec2& u, const Vec2& f,
                   Eigen::Matrix<double, 1, 4>& mixed, double& pure) const {
        const Step& st = step(n[0]);
        const double s = 1.0 / t_.bend_scale;
        const Vec2 r = r_ref - t_.pivot + u;
        pure = f.dot(-double(n[0]) * n[0] * (st.rotation * r) + st.dd_theta) * s * s;
        mixed.head<2>() = (n[0] * s) * (f.transpose() * st.rotation * quarter());
        mixed.tail<2>() = s * (f.transpose() * st.dd_theta_shift);
    }

   private:
    struct Step {
        Mat2 rotation, rotation_minus_one, d_shift, dd_theta_shift;
        Vec2 shift, d_theta, dd_theta;
    };
    const Step& step(int n) const { return steps_[n + range_]; }

    static Mat2 rotation(double a) {
        Mat2 r;
        r << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
        return r;
    }
    static Mat2 rotation_minus_one(double a) {
        const double s = std::sin(a), c1 = -2 * std::sin(0.5 * a) * std::sin(0.5 * a);
        Mat2 r;
        r << c1, -s, s, c1;
        return r;
    }
    static Mat2 quarter() {  // dR(a)/da = R(a) * quarter
        Mat2 q;
        q << 0, -1, 1, 0;
        return q;
    }

    const Topology& t_;
    int range_;
    Vec2 dt_[2] = {Vec2::Zero(), Vec2::Zero()};
    double theta_ = 0;
    std::vector<Step> steps_;
};

// Positions x -> displacements u = x - x_ref and back.
inline Vector displacement_of(const Topology& t, const Vector& x) { return x - t.reference_state(); }
inline Vector state_of(const Topology& t, const Vector& u) { return t.reference_state() + u; }

// Sparsity of a network's Hessian restricted to the free degrees of freedom (all but the pinned
// ones), built once per topology: the upper triangle in compressed columns, and for every
// particle the position in it of each entry of its local Hessian. A particle couples its
// corners and, when one of its slots is a periodic image, the period-map parameters.
struct HessianPattern {
    int n_free = 0;
    std::vector<int> free_index;               // dof -> free index, -1 if pinned
    std::vector<int> column_start, row;        // upper-triangular CSC on the free dof
    std::vector<int> slot;                     // per particle: (2C + np)^2 positions in `row`, -1 unused
    int local_size = 0;
};

// A model without a vectorised network evaluation (the overload a model header may declare,
// like hexagon.hpp, is preferred by overload resolution): the scalar loop runs.
template <class Model>
bool vectorised_finite_energy(const Model&, const Topology&, const double*, double*, double&) {
    return false;
}

// Energy and gradient of a finite network through Model::energy_lanes, kLanes particles at a
// time: the same gathers, sums and scatters, in the same order, as the scalar loop of
// Network::energy. Instantiated by the model's vectorised_finite_energy, compiled for a wide
// vector unit (network_simd.cpp).
template <class Model, int kLanes>
double finite_energy_lanes(const Model& model, const Topology& t, const double* u, double* g) {
    constexpr int C = Model::kCornerCount;
    double x[2 * C][kLanes], lane_gradient[2 * C][kLanes], e[kLanes];
    double total = 0.0;
    const int n = t.n_particles();
    for (int first = 0; first < n; first += kLanes) {
        const int lanes = std::min(kLanes, n - first);
        for (int l = 0; l < kLanes; ++l) {
            const auto& ids = t.corner[first + (l < lanes ? l : 0)];  // spare lanes repeat a particle
            for (int s = 0; s < C; ++s) {
                x[2 * s][l] = u[2 * ids[s]];
                x[2 * s + 1][l] = u[2 * ids[s] + 1];
            }
        }
        model.template energy_lanes<kLanes>(x, lane_gradient, e);
        for (int l = 0; l < lanes; ++l) {
            const auto& ids = t.corner[first + l];
            total += e[l];
            for (int s = 0; s < C; ++s) {
                g[2 * ids[s]] += lane_gradient[2 * s][l];
                g[2 * ids[s] + 1] += lane_gradient[2 * s + 1][l];
            }
        }
    }
    return total;
}

template <class Model>
struct Network {
    static constexpr int C = Model::kCornerCount;
    static_assert(C == tiling_of(Model::kTiling).corners, "the particle model's corner count must match its tiling's");
    using Corners = typename Model::Corners;
    using ParticleHessian = typename Model::Hessian;

    const Model& model;
    const Topology& topology;

    Network(const Model& model_, const Topology& topology_) : model(model_), topology(topology_) {
        if (topology.tiling_kind != Model::kTiling)
            throw std::invalid_argument(std::string("topology: a ") + topology.tiling().name +
                                        " tiling cannot carry this particle, whose tiling is the " +
                                        tiling_of(Model::kTiling).name + " one");
        for (int s = 0; s < topology.tiling().sublattices; ++s) {
            frames_[s] = frame_matrix(topology.tiling(), s);
            turned_[s] = frames_[s] != Mat2::Identity();
        }
    }

    int size() const { return 2 * topology.n_corners() + topology.n_period_parameters(); }
    int n_corner_dof() const { return 2 * topology.n_corners(); }

    PeriodMap period_map(const Vector& u) const { return PeriodMap(topology, u.data() + n_corner_dof()); }

    bool has_image(int p) const { return topology.has_image(p); }

    // Particle p's frame (tiling.hpp), or nullptr where it is the identity (the common case, kept
    // free of any arithmetic).
    const Mat2* frame(int p) const {
        const int sub = topology.sites[p][2];
        return turned_[sub] ? &frames_[sub] : nullptr;
    }
    // Corner vectors turned into (inverse: out of) the particle's frame.
    static void turn(const Mat2* f, Corners& c, bool into) {
        if (!f) return;
        for (int s = 0; s < C; ++s) {
            const Vec2 v = c.template segment<2>(2 * s);
            c.template segment<2>(2 * s) = into ? Vec2(f->transpose() * v) : Vec2(*f * v);
        }
    }
    static void turn(const Mat2* f, ParticleHessian& h) {
        if (!f) return;
        for (int a = 0; a < C; ++a)
            for (int b = 0; b < C; ++b) {
                const Mat2 block = h.template block<2, 2>(2 * a, 2 * b);
                h.template block<2, 2>(2 * a, 2 * b) = *f * block * f->transpose();
            }
    }

    // Displacements of the corners particle p sees (periodic images applied), in the lab frame.
    Corners lab_displacements(const Vector& u, const PeriodMap& map, int p) const {
        Corners c;
        const auto& ids = topology.corner[p];
        const auto& images = topology.image[p];
        for (int s = 0; s < C; ++s) {
            const Vec2 ui = u.template segment<2>(2 * ids[s]);
            c.template segment<2>(2 * s) = map.displacement(images[s], topology.reference[ids[s]], ui);
        }
        return c;
    }
    // The same in the particle's own frame: what the model evaluates.
    Corners local_displacements(const Vector& u, const PeriodMap& map, int p) const {
        Corners c = lab_displacements(u, map, p);
        turn(frame(p), c, true);
        return c;
    }

    // Corners of particle p relative to its site centre, in the lab frame, for drawing: the slot
    // offsets (the tiling's view of the model's rest shape; tests check that the two agree) plus
    // the displacements.
    Corners local_corners(const Vector& u, const PeriodMap& map, int p) const {
        Corners c = lab_displacements(u, map, p);
        for (int s = 0; s < C; ++s) c.template segment<2>(2 * s) += topology.slot_offset[topology.sites[p][2]][s];
        return c;
    }

    double particle_energy(const Vector& u, const PeriodMap& map, int p) const {
        return model.energy_of_displacement(local_displacements(u, map, p), nullptr);
    }

    // Total energy at displacement u; writes dE/du into `gradient` when given. vectorised =
    // false keeps to the scalar loop (the vectorised one gives the same bits; tests compare).
    double energy(const Vector& u, Vector* gradient, bool vectorised = true) const {
        const PeriodMap map = period_map(u);
        if (gradient) gradient->setZero(size());
        const int np = topology.n_particles();
        double total = 0.0;
        if (!gradient) {
            for (int p = 0; p < np; ++p) total += model.energy_of_displacement(local_displacements(u, map, p), nullptr);
            return total;
        }
        double* g = gradient->data();
        Corners local_gradient;
        if (topology.periodicity == Periodicity::None) {
            // A finite aggregate: no period map, corners gathered and forces scattered directly.
            if (vectorised && vectorised_finite_energy(model, topology, u.data(), g, total)) return total;
            const double* ud = u.data();
            Corners c;
            for (int p = 0; p < np; ++p) {
                const auto& ids = topology.corner[p];
                for (int s = 0; s < C; ++s) {
                    c[2 * s] = ud[2 * ids[s]];
                    c[2 * s + 1] = ud[2 * ids[s] + 1];
                }
                const Mat2* f = frame(p);
                turn(f, c, true);
                local_gradient.setZero();
                total += model.energy_of_displacement(c, &local_gradient);
                turn(f, local_gradient, false);
                for (int s = 0; s < C; ++s) {
                    g[2 * ids[s]] += local_gradient[2 * s];
                    g[2 * ids[s] + 1] += local_gradient[2 * s + 1];
                }
            }
            return total;
        }
        Mat2 d_corner;
        PeriodJacobian d_period;
        const int nc2 = n_corner_dof(), npp = topology.n_period_parameters();
        for (int p = 0; p < np; ++p) {
            const auto& ids = topology.corner[p];
            const Corners c = local_displacements(u, map, p);
            local_gradient.setZero();
            total += model.energy_of_displacement(c, &local_gradient);
            turn(frame(p), local_gradient, false);
            const auto& images = topology.image[p];
            for (int s = 0; s < C; ++s) {
                const Vec2 gs = local_gradient.template segment<2>(2 * s);
                const int id = ids[s];
                if (images[s][0] == 0 && images[s][1] == 0) {
                    g[2 * id] += gs[0];
                    g[2 * id + 1] += gs[1];
                    continue;
                }
                map.jacobian(images[s], topology.reference[id], u.template segment<2>(2 * id), d_corner, d_period);
                const Vec2 gc = d_corner.transpose() * gs;
                g[2 * id] += gc[0];
                g[2 * id + 1] += gc[1];
                for (int k = 0; k < npp; ++k) g[nc2 + k] += d_period.col(k).dot(gs);
            }
        }
        return total;
    }

    // The sparsity pattern of the Hessian on the free degrees of freedom (all but `pins`).
    HessianPattern hessian_pattern(const std::vector<int>& pins) const {
        HessianPattern pat;
        const int n = size(), npp = topology.n_period_parameters();
        pat.free_index.assign(n, 0);
        for (int i : pins) pat.free_index[i] = -1;
        for (int i = 0; i < n; ++i)
            if (pat.free_index[i] >= 0) pat.free_index[i] = pat.n_free++;
        pat.local_size = 2 * C + npp;
        const int L = pat.local_size, np = topology.n_particles();
        // Calls visit(a, b, i, j) for every entry (a, b) of particle p's local Hessian that lands
        // in the upper triangle (free row i <= free column j).
        auto for_each_entry = [&](int p, auto&& visit) {
            int dof[2 * C + kMaxPeriodParameters];
            for (int s = 0; s < C; ++s) dof[2 * s] = 2 * topology.corner[p][s], dof[2 * s + 1] = dof[2 * s] + 1;
            const int extent = has_image(p) ? L : 2 * C;
            for (int k = 0; k < npp; ++k) dof[2 * C + k] = n_corner_dof() + k;
            for (int a = 0; a < extent; ++a)
                for (int b = 0; b < extent; ++b) {
                    const int i = pat.free_index[dof[a]], j = pat.free_index[dof[b]];
                    if (i >= 0 && j >= 0 && i <= j) visit(a, b, i, j);
                }
        };
        // Every visit (row, local entry) in its column: counted, then placed (one allocation, not
        // one per column; the pattern is made once per Monte Carlo cluster), then each column
        // sorted by row, its duplicates (entries shared by neighbouring particles) merged, and
        // each visit's slot read off as the column is written.
        std::vector<int> visit_start(pat.n_free + 1, 0);
        for (int p = 0; p < np; ++p) for_each_entry(p, [&](int, int, int, int j) { ++visit_start[j + 1]; });
        for (int j = 0; j < pat.n_free; ++j) visit_start[j + 1] += visit_start[j];
        std::vector<std::pair<int, int>> visits(visit_start.back());
        std::vector<int> next(visit_start.begin(), visit_start.end() - 1);
        for (int p = 0; p < np; ++p)
            for_each_entry(p, [&](int a, int b, int i, int j) { visits[next[j]++] = {i, (p * L + a) * L + b}; });
        pat.slot.assign(static_cast<size_t>(np) * L * L, -1);
        pat.column_start.assign(pat.n_free + 1, 0);
        pat.row.reserve(visits.size());
        for (int j = 0; j < pat.n_free; ++j) {
            const auto first = visits.begin() + visit_start[j], last = visits.begin() + visit_start[j + 1];
            std::sort(first, last);
            for (auto v = first; v != last; ++v) {
                if (v == first || v->first != (v - 1)->first) pat.row.push_back(v->first);
                pat.slot[v->second] = static_cast<int>(pat.row.size()) - 1;
            }
            pat.column_start[j + 1] = static_cast<int>(pat.row.size());
        }
        return pat;
    }

    // Values of the Hessian at u on `pattern` (upper triangle, free dof). exact = true: the
    // full Hessian, J^T h J plus the curvature of the period map contracted with the particle
    // forces; exact = false: the Gauss-Newton part J^T h J only (exact where the particle
    // forces vanish, as at the rest state of the eps = 0 model used by the linear solve).
    std::vector<double> hessian(const Vector& u, const HessianPattern& pattern, bool exact) const {
        const PeriodMap map = period_map(u);
        std::vector<double> values(pattern.row.size(), 0.0);
        const int L = pattern.local_size, npp = topology.n_period_parameters();
        Eigen::Matrix<double, 2 * C, 2 * C + kMaxPeriodParameters> J;
        Eigen::Matrix<double, 2 * C + kMaxPeriodParameters, 2 * C + kMaxPeriodParameters> local;
        Mat2 d_corner;
        PeriodJacobian d_period;
        for (int p = 0; p < topology.n_particles(); ++p) {
            const Corners c = local_displacements(u, map, p);
            ParticleHessian h = ParticleHessian::Zero();
            Corners f = Corners::Zero();
            model.energy_of_displacement(c, exact ? &f : nullptr, &h);
            turn(frame(p), f, false);
            turn(frame(p), h);
            const bool image = has_image(p);
            if (!image) {
                local.template topLeftCorner<2 * C, 2 * C>() = h;
            } else {
                J.setZero();
                for (int s = 0; s < C; ++s) {
                    const int id = topology.corner[p][s];
                    map.jacobian(topology.image[p][s], topology.reference[id], u.template segment<2>(2 * id), d_corner,
                                 d_period);
                    J.template block<2, 2>(2 * s, 2 * s) = d_corner;
                    J.template block<2, kMaxPeriodParameters>(2 * s, 2 * C) = d_period;
                }
                local.noalias() = J.transpose() * h * J;
                if (exact && !map.translation_only()) {
                    const int bend = 2 * C + 2;
                    Eigen::Matrix<double, 1, 4> mixed;
                    double pure;
                    for (int s = 0; s < C; ++s) {
                        const auto& n = topology.image[p][s];
                        if (n[0] == 0) continue;
                        const int id = topology.corner[p][s];
                        map.curvature(n, topology.reference[id], u.template segment<2>(2 * id),
                                      f.template segment<2>(2 * s), mixed, pure);
                        local(bend, bend) += pure;
                        for (int k = 0; k < 2; ++k) {
                            local(bend, 2 * s + k) += mixed(k), local(2 * s + k, bend) += mixed(k);
                            local(bend, 2 * C + k) += mixed(2 + k), local(2 * C + k, bend) += mixed(2 + k);
                        }
                    }
                }
            }
            const int* slot = &pattern.slot[static_cast<size_t>(p) * L * L];
            const int extent = image ? 2 * C + npp : 2 * C;
            for (int a = 0; a < extent; ++a)
                for (int b = 0; b < extent; ++b) {
                    const int k = slot[a * L + b];
                    if (k >= 0) values[k] += local(a, b);
                }
        }
        return values;
    }

   private:
    // Each sublattice's frame as a matrix, made once, and whether it is not the identity.
    std::array<Mat2, kMaxSublattices> frames_{};
    std::array<bool, kMaxSublattices> turned_{};
};

}  // namespace pyfrustrate
