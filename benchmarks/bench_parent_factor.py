"""Can a Monte Carlo move skip the factorisation? Newton for a cluster that differs from its
parent by one particle, its linear systems solved by conjugate gradients preconditioned with the
parent's Hessian factor (made once, when the parent was relaxed), against Newton with a fresh
factorisation at every step.

The Monte Carlo relaxes every cluster a move makes from its parent's relaxed state
(``anneal(warm_start=True)``), and each Newton step factorises the cluster's Hessian anew: ~5
factorisations per relaxation in the dense box, and one relaxation of the whole aggregate per
surface move in the large one (benchmarks/README.md). The parent's factor is an obvious
preconditioner: the child's Hessian differs from it near the moved particle and by the small
relaxation elsewhere. This measures whether that pays.

Cases: a compact disk of 1 + 3R(R+1) particles (``topology.hexagon_sites(R)``; the large box's
aggregates), and the largest cluster of a dense-box state (300 particles in 30 x 30, nu = 0.4,
Gamma = 0.5, after ``--dense-sweeps`` sweeps with exact energies at T = 0.3 g: the loose
clusters of the dense run before they join into one that wraps the box), each relaxed to round-off, and their children with one particle added at a
site with two occupied neighbours or one removed from the outline (keeping the cluster
connected); ell = 5, eps = 0.01. Both paths start from the parent's relaxed displacement (the
added particle's corners from the rigid motion that best fits its known ones, as the kernel's
warm start does), take full Newton steps with backtracking, and stop at the Monte Carlo's
tolerance (largest force 1e-3 F). Both factorise with scipy's SuperLU, the only sparse
factorisation scipy has: a supernodal Cholesky (the kernel's CHOLMOD) factorises more cheaply per
flop relative to its triangular solves, so this comparison favours the preconditioned path.

Prints per case: Newton steps, conjugate-gradient iterations (preconditioned path) and
factorisations (fresh path), the steps where conjugate gradients met negative curvature (a
Hessian not positive definite) and the step fell back to a fresh factorisation, the time of
each path (min over repeats, process CPU) and their ratio, and what one SuperLU factorisation of
the child's Hessian costs in solves with it (to set against CHOLMOD's ~20, profile_kernel).

Usage: ``python benchmarks/bench_parent_factor.py [--radii 8 16] [--nu 0.9 0.4] [--dense-sweeps 100] [--repeats 3] [--quick]``
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _common  # noqa: E402  (pins BLAS threads before numpy is imported)

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402
import scipy.sparse.linalg as spla  # noqa: E402

pyfrustrate = _common.import_pyfrustrate()
from pyfrustrate import Hexagon, _kernel, continuum  # noqa: E402
from pyfrustrate.montecarlo import clusters  # noqa: E402
from pyfrustrate import topology as tp  # noqa: E402

ELL, EPS, TOL = 5.0, 0.01, 1e-3  # TOL: the Monte Carlo's, in units of the particle's force scale


class Scene:
    """Energy, gradient and Hessian of one cluster, its rigid motion pinned by three dof."""

    def __init__(self, model, sites):
        self.model, self.topology = model, tp.cluster(np.array(sites)).kernel

    def energy(self, u):
        return _kernel.energy_of_displacement(self.model, self.topology, u)

    def hessian(self, u, free):
        return sp.csc_matrix(_kernel.hessian(self.model, self.topology, u))[free][:, free].tocsc()


def neighbours(site):
    return [tuple(int(v) for v in s) for s in tp.neighbour_sites(site)]


def child_start(parent, child, u_parent):
    """The child's start: the parent's displacement on the corners they share (matched through
    the sites and slots of their particles), the rest from the rigid motion of each new particle
    that best fits its known corners (least squares, as the kernel's warm start). Also the map
    child corner -> parent corner (-1 for new ones)."""
    index = {tuple(s): i for i, s in enumerate(np.asarray(parent.topology.sites).tolist())}
    pc, cc = np.asarray(parent.topology.corners), np.asarray(child.topology.corners)
    ref = np.asarray(child.topology.reference)
    to_parent = -np.ones(child.topology.n_corners, int)
    for q, s in enumerate(np.asarray(child.topology.sites).tolist()):
        if tuple(s) in index:
            to_parent[cc[q]] = pc[index[tuple(s)]]
    u = np.zeros(2 * child.topology.n_corners)
    known = to_parent >= 0
    for c in np.flatnonzero(known):
        u[2 * c:2 * c + 2] = u_parent[2 * to_parent[c]:2 * to_parent[c] + 2]
    for corners in cc:
        k = [c for c in corners if known[c]]
        if len(k) == len(corners) or not k:
            continue
        r = ref[k]
        x = r + np.array([u[2 * c:2 * c + 2] for c in k])
        rm, xm = r.mean(0), x.mean(0)
        a, b = r - rm, x - xm
        angle = np.arctan2(np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]), np.sum(a * b)) if len(k) > 1 else 0.0
        rot = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
        for c in corners:
            if not known[c]:
                u[2 * c:2 * c + 2] = xm + rot @ (ref[c] - rm) - ref[c]
    return u, to_parent


class Negative(Exception):
    """Conjugate gradients met a direction of non-positive curvature."""


def newton(scene, u, free, tol, solve):
    """Newton with backtracking (Armijo) from u until the largest force <= tol; solve(H, rhs)
    returns the step and the work it did, or raises Negative, and the step is then solved with a
    fresh factorisation. Returns (energy, steps, work, fallbacks)."""
    e, g = scene.energy(u)
    steps = work = fallbacks = 0
    while np.max(np.abs(g)) > tol:
        if steps == 50:
            raise RuntimeError("Newton did not converge in 50 steps")
        d = np.zeros_like(u)
        H = scene.hessian(u, free)
        try:
            d[free], w = solve(H, -g[free])
            work += w
        except Negative:
            d[free], _ = fresh_factor(H, -g[free])
            fallbacks += 1
        if not g.dot(d) < 0:  # the Hessian is not positive definite here: a gradient step
            d = -g
        s = 1.0
        while True:
            e1, g1 = scene.energy(u + s * d)
            if e1 <= e + 1e-4 * s * g.dot(d) or s < 1e-8:
                break
            s *= 0.5
        u, e, g = u + s * d, e1, g1
        steps += 1
    return e, steps, work, fallbacks


def fresh_factor(H, rhs):
    return spla.splu(H).solve(rhs), 1


def parent_preconditioned(factor, to_parent_free, n_parent_free, rtol):
    """PCG on the child's Hessian with the parent's factor on the dof the two share and the
    inverse diagonal block of the new dof; returns (step, iterations), or raises Negative."""
    shared = to_parent_free >= 0
    new = ~shared

    def solve(H, rhs):
        block = np.linalg.inv(H[new][:, new].toarray()) if new.any() else None

        def apply(r):
            z = np.zeros_like(r)
            full = np.zeros(n_parent_free)
            full[to_parent_free[shared]] = r[shared]
            z[shared] = factor.solve(full)[to_parent_free[shared]]
            if block is not None:
                z[new] = block @ r[new]
            return z

        # Preconditioned conjugate gradients (written out: scipy's cg does not report negative
        # curvature, which means the child's Hessian is not positive definite).
        x = np.zeros_like(rhs)
        r = rhs.copy()
        z = apply(r)
        d = z.copy()
        rz = r.dot(z)
        target = rtol * np.linalg.norm(rhs)
        for iteration in range(1, 1001):
            Hd = H @ d
            curvature = d.dot(Hd)
            if not curvature > 0:
                raise Negative
            alpha = rz / curvature
            x += alpha * d
            r -= alpha * Hd
            if np.linalg.norm(r) <= target:
                return x, iteration
            z = apply(r)
            rz, rz_old = r.dot(z), rz
            d = z + (rz / rz_old) * d
        raise RuntimeError("PCG did not converge in 1000 iterations")

    return solve


def best_time(fn, repeats):
    times, out = [], None
    for _ in range(repeats):
        t0 = time.process_time()
        out = fn()
        times.append(time.process_time() - t0)
    return min(times), out


def connected(sites):
    occupied, seen, queue = set(sites), {sites[0]}, [sites[0]]
    for s in queue:
        for n in neighbours(s):
            if n in occupied and n not in seen:
                seen.add(n)
                queue.append(n)
    return len(seen) == len(occupied)


def children(sites):
    """One particle added at a site with two occupied neighbours, one removed from the outline
    (the first whose removal keeps the cluster connected)."""
    occupied = set(sites)
    kink = next(s for q in sites for s in neighbours(q) if s not in occupied and sum(n in occupied for n in neighbours(s)) == 2)
    edge = next(q for q in sites if sum(n in occupied for n in neighbours(q)) < 6
                and connected([s for s in sites if s != q]))
    return (("add", sites + [kink]), ("remove", [s for s in sites if s != edge]))


def case(sites, nu, repeats):
    particle = Hexagon.from_continuum(ell=ELL, nu=nu, eps=EPS)
    model, tol = particle._kernel_model, TOL * particle.force_scale
    parent = Scene(model, sites)
    relaxed = _kernel.relax_newton(model, parent.topology, 1e-10 * particle.force_scale, 10_000)
    u_parent = relaxed["displacement"]
    rows = []
    for label, child_sites in children(sites):
        child = Scene(model, child_sites)
        u0, to_parent = child_start(parent, child, u_parent)
        # Pin both dof of one shared corner and y of another far from it (the rigid motions).
        ref = np.asarray(child.topology.reference)
        shared = np.flatnonzero(to_parent >= 0)
        a = shared[0]
        b = shared[np.argmax(np.abs(ref[shared, 0] - ref[a, 0]))]
        pinned_child = [2 * a, 2 * a + 1, 2 * b + 1]
        pinned_parent = [2 * to_parent[a], 2 * to_parent[a] + 1, 2 * to_parent[b] + 1]
        free = np.setdiff1d(np.arange(u0.size), pinned_child)
        free_parent = np.setdiff1d(np.arange(u_parent.size), pinned_parent)
        position = -np.ones(u_parent.size, int)
        position[free_parent] = np.arange(free_parent.size)
        to_parent_free = np.array([position[2 * to_parent[d // 2] + d % 2] if to_parent[d // 2] >= 0 else -1 for d in free])
        # The parent's factor exists already in the scheme measured: not timed.
        factor = spla.splu(parent.hessian(u_parent, free_parent))
        t_fresh, (e_fresh, steps_fresh, factorisations, _) = best_time(
            lambda: newton(child, u0.copy(), free, tol, fresh_factor), repeats)
        best = None
        for rtol in (1e-1, 1e-2, 1e-3):
            solve = parent_preconditioned(factor, to_parent_free, free_parent.size, rtol)
            t, (e, steps, iterations, fallbacks) = best_time(lambda: newton(child, u0.copy(), free, tol, solve), repeats)
            if best is None or t < best[0]:
                best = (t, e, steps, iterations, fallbacks, rtol)
        t_pcg, e_pcg, steps_pcg, iterations, fallbacks, rtol = best
        # What one factorisation costs in solves with this library (the kernel's CHOLMOD: ~20, profile_kernel).
        H = child.hessian(u0, free)
        t_factor, lu = best_time(lambda: spla.splu(H), repeats)
        rhs = np.ones(free.size)
        t_solves, _ = best_time(lambda: [lu.solve(rhs) for _ in range(20)], repeats)
        rows.append((label, child.topology.n_particles, 2 * child.topology.n_corners, steps_fresh, factorisations,
                     t_fresh, steps_pcg, iterations, fallbacks, rtol, t_pcg, abs(e_pcg - e_fresh) / e_fresh,
                     t_factor / (t_solves / 20)))
    return rows


def dense_cluster(sweeps):
    """The largest finite cluster of the dense box after ``sweeps`` sweeps at T = 0.3 g (seed 1;
    annealed to the end, the box holds one cluster that wraps around it)."""
    particle = Hexagon.from_continuum(ell=ELL, nu=0.4, eps=EPS)
    g = float(continuum.particle_parameters(ELL, 0.4, 0.5, eps=EPS).g)
    r = pyfrustrate.anneal(particle, g=g, box=30, n=300, schedule=[(0.3 * g, 300 * sweeps)], seed=1, method="newton",
                           progress=False, cluster_moves=0.05, cluster_link=0.9, bonded_moves=0.0, surface_moves=0.0)
    finite = [c for c, rank in clusters(r.sites, 30) if rank == 0]
    return [tuple(int(v) for v in s) for s in finite[0]]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--radii", type=int, nargs="+", default=[8, 16])
    ap.add_argument("--nu", type=float, nargs="+", default=[0.9, 0.4])
    ap.add_argument("--dense-sweeps", type=int, default=100, help="sweeps of the dense box (at T = 0.3 g) before its cluster is taken")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="one small disk and a short dense run, one repeat")
    args = ap.parse_args(argv)
    radii, nus, repeats, sweeps = ([5], [0.9], 1, 20) if args.quick else (args.radii, args.nu, args.repeats, args.dense_sweeps)
    print(f"{_common.machine_line()}\n{_common.source_line()}")
    print(f"Newton for a cluster's child (one particle added or removed) from the parent's relaxed state, ell = {ELL}, "
          f"eps = {EPS}, to a largest force of {TOL} F; process CPU, min of {repeats}")
    print(f"{'parent':>14} {'nu':>4} {'move':>6} {'particles':>9} {'dof':>5} | {'fresh: steps':>12} {'factor.':>7} {'ms':>7} | "
          f"{'parent: steps':>13} {'CG it.':>6} {'fallb.':>6} {'rtol':>5} {'ms':>7} | {'parent/fresh':>12} {'dE/E':>8} "
          f"{'factor/solve':>12}")
    cases = [(f"disk R = {R}", [tuple(int(v) for v in s) for s in tp.hexagon_sites(R)], nu) for R in radii for nu in nus]
    cases.append((f"dense, {sweeps} sw.", dense_cluster(sweeps), 0.4))
    for name, sites, nu in cases:
        for (label, n, dof, sf, nf, tf, sp_, it, fb, rtol, tp_, de, fs) in case(sites, nu, repeats):
            print(f"{name:>14} {nu:4g} {label:>6} {n:9d} {dof:5d} | {sf:12d} {nf:7d} {1e3 * tf:7.1f} | {sp_:13d} {it:6d} "
                  f"{fb:6d} {rtol:5.0e} {1e3 * tp_:7.1f} | {tp_ / tf:12.2f} {de:8.1e} {fs:12.1f}")


if __name__ == "__main__":
    main()
