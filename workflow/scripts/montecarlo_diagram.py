"""Monte Carlo phase diagram (beyond the paper): for each annealing run of the grid, the kind of
its largest final aggregate (montecarlo.classify_aggregate), and its comparison with the
finite-size prediction: the final energy above the best single aggregate of the same n
(ansatz.finite_aggregates), whether that best aggregate is elongated, and the final energy above
the box's predicted ground state (the best of ground_states.box_candidates: single aggregates, a
wrapping fibre, several aggregates, the gas) with that ground state's family, and the run's own
structure in those terms (ground_states.structure, from its clusters), and how many bonds it
holds fewer than that ground state (one bond is worth g, given in bulk particle energies) and
how many that ground state holds, and the rounds of low-temperature replica exchange that followed
each anneal (montecarlo_run.py; 0: none). Each run is also judged by structure
(ground_states.structure_verdict: aggregate count, fibre or disk, fibre width within a row, against
the box's predicted ground state; the energy gate max(5 bulk energies, 2 bonds)), with its CPU
seconds (NaN for runs that did not record them). The same for the scale scans (rule montecarlo_scale), whose runs differ by seed too."""
import numpy as np

from pyfrustrate.ansatz import FiniteAggregates, energy_above_best_single
from pyfrustrate.ground_states import VERDICT_FIELDS, BoxCandidates, box_bonds, structure, structure_verdict
from pyfrustrate.io import load_npz, logging_to, save_npz
from pyfrustrate.provenance import for_job
from pyfrustrate.montecarlo import ELONGATION_THRESHOLD, classify_aggregate

with logging_to(snakemake.log[0]):  # noqa: F821
    finite, finite_nu, finite_elongated = {}, [], []
    finite_Gamma = None
    for path in snakemake.input.finite:  # noqa: F821
        f = load_npz(path)
        shapes = FiniteAggregates.from_arrays(f)
        finite[(shapes.n, round(float(f["nu"]), 9))] = (shapes, f)
        if finite_Gamma is None:
            finite_Gamma = f["Gamma"]
        elif not np.allclose(f["Gamma"], finite_Gamma):
            raise ValueError(f"{path}: its Gamma grid differs from the other finite-size predictions'")
        finite_nu.append(float(f["nu"]))
        finite_elongated.append(shapes.best_aspect_ratio(f["g"]) > ELONGATION_THRESHOLD)
    rows = []
    for path in snakemake.input.runs:  # noqa: F821
        r = load_npz(path)
        nu, Gamma, n, g = float(r["nu"]), float(r["Gamma"]), int(r["n"]), float(r["g"])
        kind, size = classify_aggregate(r["sites"], int(r["box"]))
        shapes, prediction = finite[(n, round(nu, 9))]
        gap = energy_above_best_single(r["energy"], g, prediction)
        single = "fiber" if float(shapes.best_aspect_ratio(g)) > ELONGATION_THRESHOLD else "disk"
        candidates = BoxCandidates.from_arrays(prediction)
        if candidates.box != int(r["box"]):
            raise ValueError(f"{path}: box {int(r['box'])}, but its ground states were built for box {candidates.box}")
        e_bulk = float(prediction["bulk_energy_per_particle"])
        verdict = structure_verdict(r["sites"], int(r["box"]), candidates, g, float(r["energy"]), e_bulk)
        gap_ground = verdict["gap"]
        ground = str(candidates.best_family(g))
        found = structure(r["sites"], int(r["box"]))
        ground_bonds = int(candidates.bonds[candidates.best(g)])
        bond_deficit = ground_bonds - box_bonds(r["sites"], int(r["box"]))
        exchange_rounds = int(r.get("exchange_rounds", 0))  # runs made before the stage have none
        rows.append((nu, Gamma, int(r["seed"]), kind, size, n, gap, single, gap_ground, ground, found, bond_deficit,
                     g / e_bulk, ground_bonds, exchange_rounds, verdict, float(r.get("cpu_seconds", np.nan))))
        print(f"nu={nu:g} Gamma={Gamma:g} seed {int(r['seed'])}: {kind} (largest cluster {size} of {n}); "
              f"{gap:+.1f} bulk particle energies above the best single aggregate ({single}), "
              f"{gap_ground:+.1f} above the box's ground state ({ground}); the run's structure: {found}; "
              f"{bond_deficit} bonds fewer than the ground state (a bond: {g / e_bulk:.2f} bulk particle energies)")
    (nu, Gamma, seed, kind, size, n, gap, single, gap_ground, ground, found, bond_deficit, bond_energy, ground_bonds,
     exchange_rounds, verdicts, cpu_seconds) = (np.array(c) for c in zip(*rows))
    judged = {key: np.array([np.nan if v[key] is None else v[key] for v in verdicts])
              for key in VERDICT_FIELDS}
    save_npz(snakemake.output[0], provenance=for_job(snakemake), nu=nu, Gamma=Gamma, seed=seed, kind=kind.astype(str), size=size, n=n,  # noqa: F821
             gap=gap, single_kind=single.astype(str), gap_ground=gap_ground, ground_family=ground.astype(str),
             structure=found.astype(str), bond_deficit=bond_deficit, bond_energy=bond_energy,
             ground_bonds=ground_bonds, exchange_rounds=exchange_rounds, elongation_threshold=ELONGATION_THRESHOLD,
             finite_nu=np.array(finite_nu), finite_Gamma=finite_Gamma, finite_elongated=np.array(finite_elongated),
             cpu_seconds=cpu_seconds, **{f"verdict_{key}": value for key, value in judged.items()})
