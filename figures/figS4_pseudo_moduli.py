"""Fig. S4: the deformation protocols of the supplement's pseudo-moduli (Eqs. S24-S28). Each
panel shows the corner displacements (arrows, magnified) that change the nine distances by the
protocol's vector dd and nothing else (the minimum-norm solution of J u = dd: no rigid motion),
and the pseudo-modulus dd^T M dd / A_hex of a simple particle (ell = 5, nu = 0.5, written as a
random particle) beside the continuum modulus it stands for (supplement S1)."""
import numpy as np

from pyfrustrate import Hexagon, plotting
from pyfrustrate import random_particles as rp
from pyfrustrate.io import logging_to

PANELS = (("kappa_c", r"$\kappa_c$: shift of the triangles", "kappa_c"),
          ("K", r"$K$: yellow shrinks, red grows", "K"),
          ("K_up", r"$K^\uparrow$: yellow bulk", "K"),
          ("mu_up", r"$\mu^\uparrow$: yellow shear", "mu"),
          ("K_down", r"$K^\downarrow$: red bulk", "K"),
          ("mu_down", r"$\mu^\downarrow$: red shear", "mu"))


def main(outputs, ell=5.0, nu=0.5, magnify=0.35):
    simple = Hexagon.from_continuum(ell, nu, eps=0.01)
    moduli = rp.RandomHexagon.from_hexagon(simple).moduli
    c = simple.continuum
    reference = {"kappa_c": c.kappa_c, "K": c.lam + c.mu, "mu": c.mu}
    Jp = np.linalg.pinv(rp.distance_jacobian())
    rest = rp.REST_CORNERS
    fig = plotting.figure(17.8, 10.0)
    for k, (name, title, ref) in enumerate(PANELS):
        ax = fig.add_subplot(2, 3, k + 1)
        u = (Jp @ rp.PSEUDO_MODULUS_VECTORS[name]).reshape(6, 2)
        moved = rest + magnify * u
        for (a, b), color in zip(rp.DISTANCE_PAIRS, plotting.DISTANCE_COLORS):
            ax.plot(*rest[[a, b]].T, color=color, lw=0.8, alpha=0.35)
            ax.plot(*moved[[a, b]].T, color=color, lw=1.5)
        ax.quiver(*rest.T, *(magnify * u).T, angles="xy", scale_units="xy", scale=1, width=0.012, color="k")
        ax.scatter(*rest.T, c=plotting.CORNER_COLORS, s=12,
                   edgecolors="k", linewidths=0.4, zorder=3)
        ax.set_aspect("equal")
        ax.set_xlim(-0.95, 0.95)
        ax.set_ylim(-0.9, 0.9)
        ax.axis("off")
        ax.set_title(title, fontsize=8)
        symbol = {"kappa_c": r"$\kappa_c$", "K": r"$K = \lambda + \mu$", "mu": r"$\mu$"}[ref]
        ax.text(0.5, -0.04, f"simple particle: {moduli[name]:.4g}\ncontinuum {symbol}: {reference[ref]:.4g}",
                transform=ax.transAxes, ha="center", va="top", fontsize=6.5)
    fig.text(0.5, 0.005, rf"simple particle $\ell = {ell:g}$, $\nu = {nu:g}$ ($k_c/k = {simple.kc / simple.k:.4f}$): "
             r"$\kappa_c$ and $K$ exact; $K^{\uparrow\downarrow}$, $\mu^{\uparrow\downarrow}$ within $O(k_c/k)$",
             ha="center", fontsize=7)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main([snakemake.output.pdf, snakemake.output.png])  # noqa: F821
