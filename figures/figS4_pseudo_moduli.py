"""Fig. S4: the deformation protocols of the supplement's pseudo-moduli (Eqs. S24-S28). Each
panel shows the corner displacements (arrows, magnified) that change the nine distances by the
protocol's vector dd and nothing else (the minimum-norm solution of J u = dd: no rigid motion),
and the pseudo-modulus dd^T M dd / A_hex of a simple particle (ell = 5, nu = 0.5, written as a
random particle) beside the continuum modulus it stands for (supplement S1).

(a) The coupling modulus kappa_c from a horizontal shift of the two triangles (the package's
protocol, random_particles.PSEUDO_MODULUS_VECTORS), with the definitions of the distances
d1..d9 recalled on the left. (b) The paper's equivalent protocol, a vertical shift: its dd is
computed here from the corner displacements (yellow corners up by half a unit, red ones down)
through the distance Jacobian, and its pseudo-modulus agrees with (a), as the particle's
three-fold symmetry requires for every shift direction (tests/test_pseudo_moduli_protocols.py
checks it for random particles). (c) The simultaneous bulk deformation of both triangles (K).
(d) Bulk and shear of the yellow triangle, (e) of the red one, as in the paper: the other
triangle's corners are free (grey), and so are the distances that reach them."""
import numpy as np

from pyfrustrate import Hexagon, plotting
from pyfrustrate import random_particles as rp
from pyfrustrate.io import logging_to
from pyfrustrate.provenance import for_job

YELLOW_SLOTS = np.arange(6) % 2 == 1  # odd slots yellow, even red (REST_CORNERS)
SYMBOLS = {"kappa_c": r"$\kappa_c$", "K": r"$K = \lambda + \mu$", "mu": r"$\mu$"}
# (panel letter, protocol, title, continuum modulus it stands for, free corners) of panels (c)-(e):
# in (d) and (e) the other triangle's corners are free (the supplement's grey nodes).
BULK_PANELS = (("c", "K", "$K$: yellow shrinks,\nred grows", "K", None),
               ("d", "K_up", r"$K^\uparrow$: yellow bulk", "K", ~YELLOW_SLOTS),
               ("", "mu_up", r"$\mu^\uparrow$: yellow shear", "mu", ~YELLOW_SLOTS),
               ("e", "K_down", r"$K^\downarrow$: red bulk", "K", YELLOW_SLOTS),
               ("", "mu_down", r"$\mu^\downarrow$: red shear", "mu", YELLOW_SLOTS))
FREE_COLOR = "0.6"


def shift_distances(direction) -> np.ndarray:
    """First-order change of the nine distances when the yellow triangle moves by half of the
    unit vector ``direction`` and the red one by half the other way (relative shift 1)."""
    displacement = np.where(YELLOW_SLOTS[:, None], 0.5, -0.5) * np.asarray(direction, float)
    return rp.distance_jacobian() @ displacement.ravel()


def pseudo_modulus(M, dd) -> float:
    return float(dd @ M @ dd / rp.HEXAGON_AREA)


def draw_protocol(ax, dd, title, magnify, free=None):
    """Corner displacements (arrows, magnified) of the protocol ``dd``; ``free`` (6 bools): the
    corners left free (grey, no arrow), with the distances that reach them."""
    free = np.zeros(6, bool) if free is None else np.asarray(free)
    rest = rp.REST_CORNERS
    u = (np.linalg.pinv(rp.distance_jacobian()) @ dd).reshape(6, 2)
    u[free] = 0.0  # free corners: no imposed displacement
    moved = rest + magnify * u
    for (a, b), color in zip(rp.DISTANCE_PAIRS, plotting.DISTANCE_COLORS):
        color = FREE_COLOR if free[a] or free[b] else color
        ax.plot(*rest[[a, b]].T, color=color, lw=0.8, alpha=0.35)
        ax.plot(*moved[[a, b]].T, color=color, lw=1.5, ls="--" if color == FREE_COLOR else "-")
    imposed = ~free
    # Over the corner markers: the bulk protocols' displacements are about a marker's size.
    ax.quiver(*rest[imposed].T, *(magnify * u[imposed]).T, angles="xy", scale_units="xy", scale=1, width=0.012,
              headlength=3.5, headaxislength=3.0, color="k", zorder=4)
    colors = np.where(free, FREE_COLOR, np.array(plotting.CORNER_COLORS, dtype=object))
    ax.scatter(*rest.T, c=list(colors), s=12, edgecolors="k", linewidths=0.4, zorder=3)
    ax.set_aspect("equal")
    ax.set_xlim(-0.95, 0.95)
    ax.set_ylim(-0.9, 0.9)
    ax.axis("off")
    ax.set_title(title)


def value_text(ax, text):
    ax.text(0.5, -0.04, text, transform=ax.transAxes, ha="center", va="top", fontsize=6.5)


def main(outputs, ell=5.0, nu=0.5, magnify=0.35, drawing_eps=0.15, provenance=None):
    simple = Hexagon.from_continuum(ell, nu, eps=0.01)
    particle = rp.RandomHexagon.from_hexagon(simple)
    moduli = particle.moduli
    c = simple.continuum
    reference = {"kappa_c": c.kappa_c, "K": c.lam + c.mu, "mu": c.mu}
    width, height = plotting.PAGE_WIDTH_CM, 10.0
    fig = plotting.figure(width, height)
    grid = fig.add_gridspec(2, 4, hspace=0.7, wspace=0.2, left=0.02, right=0.98, top=0.88, bottom=0.1)

    def letter(ax, label):
        """The panel letter at the left of the panel's column, above its two-line title."""
        fig.canvas.draw()  # the positions of equal-aspect axes are final after a draw
        box = ax.get_position()
        plotting.panel_label(ax, label, at_cm=(box.x0 * width, box.y1 * height + 0.95))

    # (a) the distances, and the horizontal shift of the package's kappa_c
    ax = fig.add_subplot(grid[0, 0])
    radius = np.where(YELLOW_SLOTS, 1 + drawing_eps, 1 - drawing_eps)  # mismatch exaggerated
    plotting.draw_distance_definitions(ax, rp.REST_CORNERS * radius[:, None], rp.DISTANCE_PAIRS, fontsize=7)
    ax.set_xlim(-0.95, 0.95)
    ax.set_ylim(-0.9, 0.9)
    ax.axis("off")
    ax.set_title("distances $d_1 \\ldots d_9$\n" r"(at rest, $\epsilon$ exaggerated)")
    letter(ax, "a")
    horizontal = rp.PSEUDO_MODULUS_VECTORS["kappa_c"]
    ax = fig.add_subplot(grid[0, 1])
    draw_protocol(ax, horizontal, "$\\kappa_c$: horizontal shift\nof the triangles", magnify)
    kappa_horizontal = float(moduli["kappa_c"])
    value_text(ax, f"simple particle: {kappa_horizontal:.6g}\ncontinuum {SYMBOLS['kappa_c']}: "
                   f"{reference['kappa_c']:.6g}")

    # (b) the vertical shift, its dd from the corner displacements
    vertical = shift_distances([0.0, 1.0])
    ax = fig.add_subplot(grid[0, 2])
    draw_protocol(ax, vertical, "$\\kappa_c$: vertical shift\nof the triangles", magnify)
    letter(ax, "b")
    kappa_vertical = pseudo_modulus(particle.M, vertical)
    value_text(ax, f"simple particle: {kappa_vertical:.6g}\n"
                   f"relative difference to (a): {abs(kappa_vertical / kappa_horizontal - 1):.1e}")

    # (c)-(e) the bulk and shear pseudo-moduli
    slots = [grid[0, 3]] + [grid[1, j] for j in range(4)]
    for slot, (label, name, title, ref, free) in zip(slots, BULK_PANELS):
        ax = fig.add_subplot(slot)
        draw_protocol(ax, rp.PSEUDO_MODULUS_VECTORS[name], title, magnify, free)
        if label:
            letter(ax, label)
        value_text(ax, f"simple particle: {moduli[name]:.4g}\ncontinuum {SYMBOLS[ref]}: {reference[ref]:.4g}")
    print(f"kappa_c of the simple particle: horizontal shift {kappa_horizontal:.12g}, "
          f"vertical shift {kappa_vertical:.12g}, continuum {reference['kappa_c']:.12g}")
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main([snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
