"""What "the boundary-layer length" of a random particle means, three ways (a sensitivity study
of main text Fig. 5c and the ell >= 1.5 selection of Figs. 6 and S3).

Every definition looks at a half-plane (or a deep strip) whose edge runs along a lattice vector
(``fiber(.., cut=0)``), its particles' displacements uniform along the edge; rows are
``ROW_SPACING = sqrt(3)/2`` apart.

``"slowest"``       (a) the slowest bulk mode of the half-plane, exactly, from the transfer
                    problem (``random_particles.boundary_layer_lengths``). Every random particle
                    has exactly two decaying modes ``z_1, z_2`` (``decay_modes``); when they are
                    a complex pair they share one length.
``"excited"``       (b) the slowest of those two modes that the edge actually drives: a wide
                    strip's linear response near each edge is split exactly into the two modes
                    (``edge_mode_shares``); a mode counts when its share of the edge
                    displacement reaches ``min_share``.
``"finite_depth"``  (c) the paper's protocol read literally (Fig. 5b): a slab of ``depth``
                    rows with two free edges, relaxed nonlinearly at finite ``eps`` (Newton),
                    a log-linear fit of the excess energy per particle against the distance from
                    one edge, relative to the slab's central row (what a simulation sees as "the
                    bulk") or to the exact infinite bulk.

``compare_definitions`` evaluates all of them on one sample; ``summarise`` turns that into the
numbers the paper states (P(ell >= 1.5), the median ell_pred/ell, nu per ell group).
"""
from __future__ import annotations

import numpy as np

from . import random_particles as rp
from .relaxation import StiffnessCache, particle_corners, particle_energies, relax
from .topology import fiber

DEFINITIONS = ("slowest", "excited", "finite_depth")
REFERENCES = ("centre", "bulk")


def decay_modes(M) -> np.ndarray:
    """The two decaying modes ``z`` (``|z| < 1``) of the half-plane's transfer problem.

    Slowest first (a complex pair has one modulus). Their decay lengths are
    ``-ROW_SPACING / ln|z|`` (``decay_length``).

    Parameters
    ----------
    M : array_like, shape (9, 9)
        A random particle's elasticity matrix (``random_particles.elasticity_matrices``).

    Returns
    -------
    ndarray of complex, shape (2,)

    Raises
    ------
    ValueError
        If ``M`` is not a valid elasticity matrix.
    RuntimeError
        If the transfer problem does not have exactly two decaying modes.
    """
    z = rp.transfer_roots(rp.rest_hessian(rp.checked_matrix(M)))
    z = z[np.argsort(np.abs(z - 1))][4:]  # the four roots at z = 1 are translations and strains
    inside = z[np.abs(z) < 1]
    # The companion pencil pads the degree-8 polynomial with roots at z = 0 (numerically tiny):
    # the two decaying modes are the two largest inside the unit circle.
    inside = inside[np.argsort(-np.abs(inside))][:2]
    if inside.size != 2 or np.abs(inside[1]) < 1e-9:
        raise RuntimeError(f"decay_modes: expected two decaying modes, found {np.round(inside, 12)}")
    return inside


def decay_length(z) -> np.ndarray:
    """Decay length of a mode ``z``: ``-ROW_SPACING / ln|z|``.

    Parameters
    ----------
    z : array_like of complex
        Modes (``decay_modes``), ``|z| < 1``.

    Returns
    -------
    ndarray
        Lattice spacings.
    """
    return -rp.ROW_SPACING / np.log(np.abs(z))


class _Strip:
    """A straight strip of ``width`` rows (cut 0) with its rows ordered from the top edge, its
    reference corners and a stiffness cache: one per width, reused over particles."""

    def __init__(self, width: int):
        self.width = int(width)
        self.topology = fiber(self.width, 0, curved=False)
        self.cache = StiffnessCache(self.topology)
        probe = rp.RandomHexagon(np.eye(9))
        self.reference = particle_corners(probe, self.topology, self.topology.reference_state())
        self.from_top = np.argsort(-self.reference.mean(axis=1)[:, 1])


_STRIPS: dict[int, _Strip] = {}


def _strip(width: int) -> _Strip:
    if width not in _STRIPS:
        _STRIPS[width] = _Strip(width)
    return _STRIPS[width]


def edge_mode_shares(M, width: int | None = None) -> dict:
    """Each decaying mode's share of the edge displacement, at the top and the bottom edge.

    The linear response of a straight strip of ``width`` rows is, from the third row inwards,
    exactly ``a + b j + c (-1)^j + sum_i c_i z_i^j`` per particle row ``j`` (12 corner
    displacements each): ``a + b j`` are translations and uniform strains, ``(-1)^j`` is the
    cell's stretch seen through the alternating positions of the rows in the periodic cell,
    ``z_i`` the two modes of ``decay_modes``. The coefficients come from a least-squares fit over
    the half of the strip nearest each edge (residual ~1e-13 of the displacement: the fit is
    exact, and ``residual`` reports it); a mode's share is ``|c_i| / (|c_1| + |c_2|)``, its
    displacement at the edge row relative to the other's.

    Parameters
    ----------
    M : array_like, shape (9, 9)
        A random particle's elasticity matrix (``random_particles.elasticity_matrices``).
    width : int, optional
        Rows of the strip (default: 40 slowest lengths, at least 60 rows).

    Returns
    -------
    dict
        ``z`` (2,), ``ell`` (2,, lattice spacings), ``share`` (2 edges, 2 modes: top then bottom)
        and ``residual`` (relative).

    Raises
    ------
    ValueError
        If ``M`` is not a valid elasticity matrix, or the strip too large for memory.
    """
    z = decay_modes(M)
    ell = decay_length(z)
    if width is None:
        width = int(np.clip(20 * np.ceil(2 * ell[0] / rp.ROW_SPACING), 60, 2000))
    strip = _strip(int(width))
    particle = rp.RandomHexagon(M, 0.01)
    r = relax(particle, strip.topology, method="linear", cache=strip.cache)
    u = (particle_corners(particle, strip.topology, r.state) - strip.reference)[strip.from_top].reshape(strip.width, 12)
    j = np.arange(2, strip.width // 2)
    basis = np.stack([np.ones(j.size), j.astype(float), (-1.0) ** j, z[0] ** j, z[1] ** j], axis=1)
    shares, residual = np.empty((2, 2)), 0.0
    for edge, rows in enumerate((u, u[::-1])):
        coef, *_ = np.linalg.lstsq(basis, rows[j].astype(complex), rcond=None)
        misfit = np.abs((basis @ coef).real - rows[j]).max() / max(np.abs(rows[j]).max(), 1e-300)
        residual = max(residual, float(misfit))
        amplitude = np.linalg.norm(coef[3:], axis=1)
        shares[edge] = amplitude / amplitude.sum()
    return {"z": z, "ell": ell, "share": shares, "residual": residual}


def excited_boundary_layer_length(M, min_share: float = 0.1, width: int | None = None) -> float:
    """Definition (b): the decay length of the slowest mode carrying at least ``min_share`` of the
    edge displacement at either edge of a strip (``edge_mode_shares``).

    A complex pair of modes has one length, that of definition (a).

    Parameters
    ----------
    M : array_like, shape (9, 9)
        A random particle's elasticity matrix (``random_particles.elasticity_matrices``).
    min_share : float, optional
        In (0, 0.5].
    width : int, optional
        Rows of the strip (``edge_mode_shares``).

    Returns
    -------
    float
        Lattice spacings.

    Raises
    ------
    ValueError
        For ``min_share`` out of range or an invalid ``M``.
    """
    if not (0 < min_share <= 0.5):
        raise ValueError(f"min_share must lie in (0, 0.5], got {min_share!r}")
    modes = edge_mode_shares(M, width)
    if abs(modes["z"][0].imag) > 1e-12:
        return float(modes["ell"][0])
    slow_excited = modes["share"][:, 0].max() >= min_share
    return float(modes["ell"][0] if slow_excited else modes["ell"][1])


def finite_depth_boundary_layer_length(M, depth: int, eps: float = 0.01, reference: str = "centre",
                                       first_row: int = 1, last_row: int | None = None, tol: float = 1e-8) -> float:
    """Definition (c), the paper's protocol read literally.

    A slab of ``depth`` rows (free edges, periodic along them) relaxed at mismatch ``eps``
    (Newton, nonlinear), and the decay length of a log-linear fit of ``|e_j / e_ref - 1|``
    against the distance ``(j + 1/2) ROW_SPACING`` from the top edge, over rows ``first_row`` to
    ``last_row`` (default: two rows before the slab's centre; the fit then also sees the far
    edge's tail, which flattens the profile near the centre).

    Parameters
    ----------
    M : array_like, shape (9, 9)
        A random particle's elasticity matrix (``random_particles.elasticity_matrices``).
    depth : int
        Rows of the slab, ``>= 6``.
    eps : float, optional
        Mismatch.
    reference : {'centre', 'bulk'}, optional
        ``'centre'``: the central row's energy, as a simulation would take its "bulk";
        ``'bulk'``: the exact infinite bulk (``RandomHexagon.bulk_energy_per_particle``).
    first_row, last_row : int, optional
        Rows fitted (at least three, before the centre).
    tol : float, optional
        Relaxation tolerance (``relax``).

    Returns
    -------
    float
        Lattice spacings; ``inf`` when the fit does not decay.

    Raises
    ------
    ValueError
        For a bad depth, reference or row range.
    """
    depth = int(depth)
    if depth < 6:
        raise ValueError(f"depth must be at least 6 rows, got {depth!r}")
    if reference not in REFERENCES:
        raise ValueError(f"reference must be one of {REFERENCES}, got {reference!r}")
    last = depth // 2 - 2 if last_row is None else int(last_row)  # the central row is the reference: stop before it
    if not (last <= depth // 2 - 2):
        raise ValueError(f"last_row must lie before the slab's centre (<= {depth // 2 - 2} for depth {depth}), "
                         f"got {last_row!r}")
    if not (0 <= first_row <= last - 2):
        raise ValueError(f"first_row must lie in [0, {last - 2}] for depth {depth} (three rows to fit), "
                         f"got {first_row!r}")
    strip = _strip(depth)
    particle = rp.RandomHexagon(M, eps)
    r = relax(particle, strip.topology, method="newton", tol=tol, cache=strip.cache)
    e = particle_energies(particle, strip.topology, r.state)[strip.from_top]
    e_ref = e[depth // 2] if reference == "centre" else particle.bulk_energy_per_particle
    rows = np.arange(first_row, last + 1)
    excess = np.abs(e[rows] / e_ref - 1)
    kept = excess > 0
    if kept.sum() < 2:
        return float("inf")
    slope = np.polyfit((rows[kept] + 0.5) * rp.ROW_SPACING, np.log(excess[kept]), 1)[0]
    return float(-1 / slope) if slope < 0 else float("inf")


def compare_definitions(Ms, depths=(10, 20, 40), eps: float = 0.01, min_shares=(0.1, 0.5),
                        progress: bool = False) -> dict:
    """Every definition of ell for each matrix of a sample.

    Parameters
    ----------
    Ms : array_like, shape (n, 9, 9)
        Elasticity matrices.
    depths : iterable of int, optional
        Slab depths of definition (c).
    eps : float, optional
        Mismatch of definition (c).
    min_shares : iterable of float, optional
        Thresholds of definition (b).
    progress : bool, optional
        Show a progress bar.

    Returns
    -------
    dict of ndarray, each of shape (n,)
        Keyed ``slowest``, ``excited_share{s}`` per ``min_shares`` and
        ``finite_depth{D}_{reference}`` per depth and reference, plus ``ell_fast`` (the faster
        mode), ``share_top``/``share_bottom`` (the slowest mode's share at each edge) and the
        pseudo-moduli ``nu`` and ``ell_pred``. Lengths in lattice spacings.

    Raises
    ------
    ValueError
        For a wrong shape of ``Ms``.
    """
    from tqdm.auto import tqdm
    Ms = np.asarray(Ms, float)
    if Ms.ndim != 3 or Ms.shape[1:] != (9, 9):
        raise ValueError(f"Ms must have shape (n, 9, 9), got {Ms.shape}")
    n = len(Ms)
    moduli = rp.pseudo_moduli(Ms)
    out = {"slowest": rp.boundary_layer_lengths(Ms), "nu": np.asarray(moduli["nu"]),
           "ell_pred": np.asarray(moduli["ell_pred"])}
    keys = ["ell_fast", "share_top", "share_bottom"] + [f"excited_share{s:g}" for s in min_shares]
    keys += [f"finite_depth{D}_{ref}" for D in depths for ref in REFERENCES]
    out |= {k: np.empty(n) for k in keys}
    for i in tqdm(range(n), disable=not progress, desc="ell definitions", mininterval=2.0):
        modes = edge_mode_shares(Ms[i])
        paired = abs(modes["z"][0].imag) > 1e-12
        out["ell_fast"][i] = modes["ell"][1]
        out["share_top"][i], out["share_bottom"][i] = modes["share"][:, 0]
        for s in min_shares:
            excited = paired or modes["share"][:, 0].max() >= s
            out[f"excited_share{s:g}"][i] = modes["ell"][0] if excited else modes["ell"][1]
        for D in depths:
            for ref in REFERENCES:
                out[f"finite_depth{D}_{ref}"][i] = finite_depth_boundary_layer_length(Ms[i], D, eps, ref)
    return out


def definition_names(study: dict) -> list[str]:
    """The ell columns of a ``compare_definitions`` result, in table order.

    Parameters
    ----------
    study : dict
        A ``compare_definitions`` result.

    Returns
    -------
    list of str
    """
    return ["slowest"] + sorted(k for k in study if k.startswith("excited_share")) + \
        sorted((k for k in study if k.startswith("finite_depth")), key=lambda k: (int(k[12:].split("_")[0]), k))


def summarise(study: dict, ell_groups=(0.0, 1.0, 1.5, np.inf), threshold: float = 1.5) -> dict:
    """For each ell definition of a ``compare_definitions`` result, the numbers the paper states.

    Parameters
    ----------
    study : dict
        A ``compare_definitions`` result.
    ell_groups : sequence of float, optional
        Edges of the ell groups.
    threshold : float, optional
        The ell of ``P_above``.

    Returns
    -------
    dict of dict
        Per definition: ``P_above`` = P(ell >= threshold), ``median_ratio`` = median
        ell_pred/ell, ``above_one`` = P(ell_pred > ell), all over the particles whose fit decays
        (``not_decaying`` is the fraction whose does not), and per ell group the fraction of
        draws, the median nu, P(nu < 0) and P(nu < -0.5).
    """
    nu, pred = np.asarray(study["nu"]), np.asarray(study["ell_pred"])
    table = {}
    for name in definition_names(study):
        ell = np.asarray(study[name], float)
        finite = np.isfinite(ell) & (ell > 0)
        group = np.where(finite, np.digitize(ell, ell_groups) - 1, -1)
        ratio = pred[finite] / ell[finite]
        row = {"P_above": float(np.mean(ell[finite] >= threshold)), "median_ratio": float(np.median(ratio)),
               "above_one": float(np.mean(ratio > 1)), "not_decaying": float(np.mean(~finite))}
        for g in range(len(ell_groups) - 1):
            members = group == g
            row[f"group{g}_fraction"] = float(members.mean())
            row[f"group{g}_median_nu"] = float(np.median(nu[members])) if members.any() else float("nan")
            for cut in (0.0, -0.5):
                below = float(np.mean(nu[members] < cut)) if members.any() else float("nan")
                row[f"group{g}_P_nu_below_{cut:g}"] = below
        table[name] = row
    return table
