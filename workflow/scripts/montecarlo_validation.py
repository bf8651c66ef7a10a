"""results/montecarlo/validation.json (issue 33, item 5): one record per point of the fixed-size
validation, W*_MC (fibres) or n*_MC (disks) per seed from the quenched samples' energy per particle
(montecarlo.fixed_size.size_of_lowest_energy) against the ansatz's best straight fibre or best
hexagonal disk and the continuum's optimum; the profile's scale; the wall time per sample and a
power law of the time per attempted move against the particles, to estimate larger samples;
the two-sided checks (item 4); the grand-canonical samples (item 2), one record
per temperature, chemical potential and seed, and W* per temperature and seed where <E>/<n> crosses
mu (montecarlo.grand_canonical.threshold_width) against the ansatz's; large_runs (item 3), one
record per run of the scale scans (results/montecarlo/scale.npz, ground_states.structure_verdict)
with its structure_match."""
import json

import numpy as np

from pyfrustrate.ground_states import VERDICT_FIELDS
from pyfrustrate.io import load_npz, logging_to, save_json
from pyfrustrate.montecarlo import fixed_size, grand_canonical
from pyfrustrate.provenance import for_job

p = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)


def load(path):
    with open(path) as f:
        return json.load(f)


with logging_to(snakemake.log[0]):  # noqa: F821
    samples = [load(path) for path in snakemake.input.samples]  # noqa: F821
    records, seconds, moves, particles = [], [], [], []
    for point in map(load, snakemake.input.points):  # noqa: F821
        mine = {(s["size"], s["seed"]): s for s in samples
                if (s["scan"], s["nu"], s["Gamma"]) == (point["scan"], point["nu"], point["Gamma"])}
        sizes, g = point["sizes"], point["g"]
        per_seed = {key: [[mine[size, seed][key] for size in sizes] for seed in p.seeds]
                    for key in ("energy_per_particle", "outside", "wraps", "seconds", "moves", "n", "bonds")}
        # A sample kept its structure when it ended as one aggregate wrapping the box once (a
        # fibre) or not at all (a disk).
        wraps_as_seeded = 1 if point["scan"] == "fibre" else 0
        kept = [[o == 0 and w == wraps_as_seeded for o, w in zip(*rows)]
                for rows in zip(per_seed["outside"], per_seed["wraps"])]
        optima = [fixed_size.size_of_lowest_energy(sizes, e) for e in per_seed["energy_per_particle"]]
        record = dict(scan=point["scan"], nu=point["nu"], Gamma=point["Gamma"], g=g, ell=point["ell"],
                      eps=point["eps"], sizes=sizes, seeds=list(p.seeds),
                      energy_per_particle_over_g=(np.array(per_seed["energy_per_particle"]) / g).tolist(),
                      outside=per_seed["outside"], wraps=per_seed["wraps"], structure_kept=kept,
                      seconds=per_seed["seconds"],
                      hold_temperature_over_g=point["hold_temperature_over_g"], window=point["window"],
                      bracketed=[b for _, b in optima])
        best = [int(size) for size, _ in optima]
        # The vertex of a parabola through each seed's e(size) (None where it has no minimum).
        fitted = [fixed_size.fitted_optimum(sizes, e) for e in per_seed["energy_per_particle"]]
        fitted = [None if np.isnan(f) else round(f, 2) for f in fitted]
        if point["scan"] == "fibre":
            W = point["W_ansatz"]
            fibre = np.array(point["fibre_energy_per_particle"])
            n = np.array(per_seed["n"])
            # Bonds' worth by which each quenched fibre lies above the relaxed straight fibre of its
            # width (0: the sample found the perfect outline).
            excess = n * (np.array(per_seed["energy_per_particle"]) - fibre[np.array(sizes) - 1]) / g
            # What one row of width is worth in a sample of the optimal width: the energy a sample
            # must resolve to tell W* from its neighbours, in bonds.
            row = min(fibre[W - 2], fibre[W]) - fibre[W - 1] if W >= 2 else fibre[W] - fibre[W - 1]
            record.update(W_mc=best, W_ansatz=W, W_continuum=point["continuum"]["W_rows"],
                          W_mc_spread=max(best) - min(best), W_mc_fitted=fitted,
                          within_one_row=[abs(b - W) <= 1 for b in best],
                          excess_over_straight_fibre_bonds=excess.tolist(),
                          row_resolution_bonds=float(p.fibre_length * W * row / g), fibre_length=p.fibre_length)
        else:
            n_star = point["n_ansatz"]
            disk = np.array(point["disk_energy_per_particle"])
            R = point["R_ansatz"]
            neighbours = [disk[R - 2]] if R >= 2 else []
            neighbours += [disk[R]] if R < len(disk) else []
            record.update(n_mc=best, n_ansatz=n_star, R_ansatz=R, n_continuum=point["continuum"]["n_disk"],
                          n_mc_spread=max(best) - min(best), n_mc_fitted=fitted,
                          within_15_percent=[abs(b - n_star) <= 0.15 * n_star for b in best],
                          hexagon_resolution_bonds=float(n_star * (min(neighbours) - disk[R - 1]) / g))
        records.append(record)
        seconds += sum(per_seed["seconds"], [])
        moves += sum(per_seed["moves"], [])
        particles += sum(per_seed["n"], [])
        print(f"{record['scan']} nu={record['nu']} Gamma={record['Gamma']}: best sizes per seed {best}, ansatz "
              f"{record.get('W_ansatz', record.get('n_ansatz'))}, hold {record['hold_temperature_over_g']:.3g} g")
    seconds, moves, particles = map(np.array, (seconds, moves, particles))
    # Time per attempted move against the particles, a power law fitted in logarithms: the
    # relaxations grow with the aggregate.
    exponent, log_prefactor = np.polyfit(np.log(particles), np.log(seconds / moves), 1)
    per_sweep = {int(n): float(np.exp(log_prefactor) * n ** exponent * n) for n in p.estimate_particles}
    timing = dict(seconds_per_sample_mean=float(seconds.mean()), seconds_per_sample_max=float(seconds.max()),
                  seconds_total=float(seconds.sum()), samples=int(seconds.size),
                  seconds_per_move_exponent=float(exponent), seconds_per_move_prefactor=float(np.exp(log_prefactor)),
                  estimated_seconds_per_sweep=per_sweep,
                  note="one core per sample; the estimate extrapolates the fitted power law")
    # Two-sided checks, one record per point and competitor: the predicted state persists (one
    # aggregate of its kind, fixed_size.persists) and the competitor, with the same seed, never
    # ends below it.
    checks = [load(path) for path in snakemake.input.two_sided]  # noqa: F821
    two_sided = []
    for key in sorted({(c["scan"], c["nu"], c["Gamma"], c["competitor_rule"]) for c in checks}):
        runs = sorted((c for c in checks if (c["scan"], c["nu"], c["Gamma"], c["competitor_rule"]) == key),
                      key=lambda c: c["seed"])
        predicted = [round(c["predicted"]["energy_over_g"], 3) for c in runs]
        competitor = [round(c["competitor"]["energy_over_g"], 3) for c in runs]
        persists = [c["predicted"]["persists"] for c in runs]
        not_below = [e_c >= e_p for e_c, e_p in zip(competitor, predicted)]
        first = runs[0]
        two_sided.append(dict(scan=key[0], nu=key[1], Gamma=key[2], competitor_rule=key[3], n=first["n"],
                              box=first["box"], predicted_kind=first["predicted_kind"],
                              predicted_state=first["predicted_state"], competitor_state=first["competitor_state"],
                              ansatz_margin_per_particle_over_g=first["ansatz_margin_per_particle_over_g"],
                              seeds=[c["seed"] for c in runs], predicted_energy_over_g=predicted,
                              competitor_energy_over_g=competitor,
                              predicted_cluster_sizes=[c["predicted"]["cluster_sizes"] for c in runs],
                              competitor_cluster_sizes=[c["competitor"]["cluster_sizes"] for c in runs],
                              persists=persists, competitor_not_below=not_below,
                              holds=all(persists) and all(not_below)))
        print(f"two-sided {key}: {first['predicted_state']} {predicted} against {first['competitor_state']} "
              f"{competitor} (E/g), holds {two_sided[-1]['holds']}")
    # Grand-canonical samples (item 2): <W>(mu) per temperature and seed, and W* where the scan
    # crosses its threshold <E>/<n> = mu.
    grand = sorted(map(load, snakemake.input.grand),  # noqa: F821
                   key=lambda s: (s["T_over_g"], s["seed"], s["mu_over_g"]))
    grand_canonical_records = [dict((k, s[k]) for k in (
        "nu", "Gamma", "T_over_g", "mu_over_g", "mu_offset_over_g", "seed", "W_mean", "W_std", "n_mean", "n_std",
        "energy_per_particle_over_g", "wraps", "seconds", "length")) | dict(W_end=s["W_trace"][-1]) for s in grand]
    # The ansatz's width against mu at T = 0: the energy of the W-th row, W e(W) - (W - 1) e(W - 1),
    # is the mu at which a straight fibre of W rows and one of W - 1 have one grand potential.
    widths = np.arange(1, len(grand[0]["fibre_energy_per_particle_over_g"]) + 1) if grand else np.zeros(0)
    row_energy = np.diff(np.r_[0.0, widths * np.array(grand[0]["fibre_energy_per_particle_over_g"])]) if grand else widths
    W_star = []
    for temperature_index, T in enumerate(sorted({s["T_over_g"] for s in grand})):
        per_seed = []
        for seed in sorted({s["seed"] for s in grand}):
            scan = [s for s in grand if s["T_over_g"] == T and s["seed"] == seed]
            W, mu = grand_canonical.threshold_width([s["mu_over_g"] for s in scan], [s["W_mean"] for s in scan],
                                                    [s["energy_per_particle_over_g"] for s in scan])
            per_seed.append((seed, W, mu, [round(s["W_mean"], 2) for s in scan],
                             [round(s["W_trace"][-1], 2) for s in scan]))
        found = [W for _, W, *_ in per_seed if np.isfinite(W)]
        # temperature_index (0: the coldest) names a record whatever the profile's temperatures.
        W_star.append(dict(T_over_g=T, temperature_index=temperature_index, seeds=[s for s, *_ in per_seed],
                           W_star=[None if np.isnan(W) else round(W, 2) for _, W, *_ in per_seed],
                           mu_threshold_over_g=[None if np.isnan(mu) else round(mu, 4) for _, _, mu, *_ in per_seed],
                           W_mean_by_offset=[means for *_, means, _ in per_seed],
                           W_end_by_offset=[ends for *_, ends in per_seed],
                           W_star_mean=round(float(np.mean(found)), 2) if found else None,
                           W_star_spread=round(float(np.ptp(found)), 2) if found else None,
                           W_ansatz=grand[0]["W_ansatz"], threshold_ansatz_over_g=grand[0]["threshold_over_g"],
                           ansatz_row_energy_over_g=row_energy.tolist()))
        print(f"grand-canonical T = {T:g} g: W* per seed {W_star[-1]['W_star']} (ansatz {grand[0]['W_ansatz']})")
    # The scale scans' runs judged by structure (issue 33, item 3), one record per run.
    scale = load_npz(snakemake.input.scale[0])  # noqa: F821
    large_runs = []
    for k in range(len(scale["seed"])):
        at = (round(float(scale["nu"][k]), 9), round(float(scale["Gamma"][k]), 9))
        fields = {key: scale[f"verdict_{key}"][k].item() for key in VERDICT_FIELDS}
        fields = {key: None if isinstance(v, float) and np.isnan(v) else v for key, v in fields.items()}
        # A count of disks went through the npz as a float column (NaN where not fused disks).
        for key in ("lobes", "lobes_predicted"):
            fields[key] = None if fields[key] is None else int(fields[key])
        large_runs.append(dict(scans=[s for s, nu, G in p.large_points if (round(nu, 9), round(G, 9)) == at],
                               nu=at[0], Gamma=at[1], seed=int(scale["seed"][k]), n=int(scale["n"][k]),
                               gap=float(scale["gap_ground"][k]), cpu_seconds=float(scale["cpu_seconds"][k]),
                               **fields))
    cpu_seconds = [r["cpu_seconds"] for r in large_runs if np.isfinite(r["cpu_seconds"])]
    large_summary = dict(runs=len(large_runs), structure_match=sum(r["structure_match"] for r in large_runs),
                         gap_ok=sum(r["gap_ok"] for r in large_runs),
                         structure_match_and_gap_ok=sum(r["structure_match"] and r["gap_ok"] for r in large_runs),
                         structure_within_gate=sum(r["structure_within_gate"] for r in large_runs),
                         structure_within_gate_and_gap_ok=sum(r["structure_within_gate"] and r["gap_ok"]
                                                              for r in large_runs),
                         below_prediction=sum(r["below_prediction"] for r in large_runs),
                         cpu_seconds_max=max(cpu_seconds) if cpu_seconds else None,
                         cpu_minutes_max=max(cpu_seconds) / 60 if cpu_seconds else None)
    print(f"large runs: {large_summary}")
    save_json(snakemake.output[0], dict(  # noqa: F821
        points=records, scale=dict(p.scale), timing=timing, large_runs=large_runs, large_summary=large_summary,
        two_sided=two_sided, grand_canonical=grand_canonical_records, grand_canonical_W_star=W_star),
        provenance=for_job(snakemake))  # noqa: F821
    print(f"{seconds.size} samples, {seconds.mean():.1f} s each on average (max {seconds.max():.1f} s)")
