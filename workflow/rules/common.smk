def pick(section, *keys):
    """The named entries of a config section, for a rule's params: each rule gets exactly the
    values its script uses, so that changing a key reruns only the jobs that read it."""
    return {key: section[key] for key in keys}


def key_sorted(value):
    """``value`` with the keys of every mapping in it sorted, at every depth: a param that holds a
    configuration section then reads the same whatever the key order of the file it came from
    (Snakemake reruns a job whose params changed, and compares them as written)."""
    if isinstance(value, dict):
        return {key: key_sorted(value[key]) for key in sorted(value)}
    if isinstance(value, list):
        return [key_sorted(item) for item in value]
    return value


def per_box(section, key):
    """A Monte Carlo run's value of ``key`` for its box kind (the wildcard ``kind``): the sparse
    runs read ``key``, the dense and large ones ``dense_key`` and ``large_key``."""
    return lambda w: section[key if w.kind.startswith("sparse") else f"{w.kind.split('_')[0]}_{key}"]


def exchange_after_anneal(section):
    """A Monte Carlo run's low-temperature replica exchange after its anneal (montecarlo_run.py):
    its rounds for the run's box kind (per_box) and, only when there are any, the ladder's
    temperatures (in units of g) and size and the least Gamma that takes the stage, so that a run
    without the stage never reads them."""
    rounds = per_box(section, "exchange_rounds")

    def params(w):
        if not rounds(w):
            return dict(rounds=0)
        return dict(rounds=rounds(w), temperatures=section["exchange_temperatures"],
                    replicas=section["exchange_replicas"], Gamma_min=section["exchange_Gamma_min"])

    return params


def figure_png(name):
    """A figure's PNG, marked for `snakemake --report` with its caption (workflow/report/) under
    the part of the paper it belongs to."""
    category = "Beyond the paper" if name.startswith("figX") else "Supplement" if name.startswith("figS") else "Main text"
    return report(f"{FIGURES}/{name}.png", caption=f"../report/{name}.rst", category=category)


# Names shared by the rules: the nu grid of the ansatz diagrams and the catalogue file of a particle.
ANSATZ = config["ansatz"]
DIAGRAM_NU = sorted({round(min(float(x), ANSATZ["nu_max"]), 4) for x in np.linspace(0, 1, ANSATZ["nu_count"])})


def catalogue_file(ell, nu):
    return f"results/ansatz/catalogue/ell{float(ell):g}_nu{float(nu):g}.npz"

MC = config["montecarlo"]


def mc_run_params():
    """The params of a Monte Carlo run, every kind (montecarlo_run.py)."""
    return dict(
        nu=lambda w: float(w.nu),
        Gamma=lambda w: float(w.Gamma),
        seed=lambda w: int(w.seed),
        kind=lambda w: w.kind.split("_")[0],
        convention=lambda w: w.kind.split("_")[1] if "_" in w.kind else "measured",
        tiling="hexagon",
        checkpoint_stem=lambda w: f"results/montecarlo/checkpoints/{w.kind}_nu{w.nu}_G{w.Gamma}_seed{w.seed}",
        n=per_box(MC, "n"),
        box=per_box(MC, "box"),
        method=per_box(MC, "method"),
        sweeps=per_box(MC, "sweeps"),
        bonded_moves=per_box(MC, "bonded_moves"),
        surface_moves=per_box(MC, "surface_moves"),
        exchange=exchange_after_anneal(MC),
        **pick(MC, "ell", "eps", "tol", "cluster_moves", "cluster_link"),
    )


def mc_run_file(nu, Gamma, seed, kind="sparse", convention="measured"):
    """One annealing run; ``kind`` picks the box: 'sparse' (n, box), 'dense' (dense_n, dense_box:
    the bottom row of Fig. 3b) or 'large' (large_n, large_box: figX_mc_finite_size);
    ``convention`` how Gamma maps to g (continuum.BINDING_CONVENTIONS): the supplement's runs are
    the kinds 'sparse_supplement' and 'dense_supplement'."""
    suffix = "" if convention == "measured" else f"_{convention}"
    return f"results/montecarlo/runs/{kind}{suffix}_nu{float(nu):g}_G{float(Gamma):g}_seed{seed}.npz"


def finite_aggregate_file(n, nu):
    """The best single aggregates of n particles at this nu (finite-size prediction)."""
    return f"results/montecarlo/finite/n{int(n)}_nu{float(nu):g}.npz"


def mc_snapshot_files(convention="measured"):
    """The runs of Fig. 3b: the fibre scan (nu fixed, Gamma rising), the dense disk scan (the
    bottom row), the nu scan at fixed Gamma, and every seed at the extra point; with Gamma read
    in the binding ``convention``."""
    first = MC["seeds"][0]
    runs = [(MC["fiber_scan_nu"], G, first) for G in MC["fiber_scan_Gamma"]]
    runs += [(MC["disk_scan_nu"], G, first, "dense") for G in MC["disk_scan_Gamma"]]
    runs += [(nu, MC["nu_scan_Gamma"], first) for nu in MC["nu_scan_nu"]]
    G, nu = MC["extra_seed_point"]
    runs += [(nu, G, seed) for seed in MC["seeds"]]
    return sorted({mc_run_file(*r, convention=convention) if len(r) == 4 else
                   mc_run_file(*r, "sparse", convention) for r in runs})


def mc_finite_size_files():
    """The runs of figX_mc_finite_size: the fibre scan and the nu scan in the large box, and the
    sparse (paper-size) runs of the same fibre scan for comparison."""
    first = MC["seeds"][0]
    runs = [(MC["fiber_scan_nu"], G, first, "large") for G in MC["large_scan_Gamma"]]
    runs += [(nu, MC["nu_scan_Gamma"], first, "large") for nu in MC["large_nu_scan_nu"]]
    runs += [(MC["fiber_scan_nu"], G, first) for G in MC["fiber_scan_Gamma"]]
    return sorted({mc_run_file(*r) for r in runs})


def mc_scale_points():
    """(scan, nu, Gamma) of figX_mc_scale: Fig. 3b's three line scans (the fibre scan, the disk
    scan, the nu scan) in the large box, each run with every seed of large_seeds."""
    points = [("fibre", MC["fiber_scan_nu"], G) for G in MC["large_scan_Gamma"]]
    points += [("disk", MC["disk_scan_nu"], G) for G in MC["large_scan_Gamma"]]
    points += [("nu", nu, MC["nu_scan_Gamma"]) for nu in MC["large_nu_scan_nu"]]
    return points


def mc_scale_files():
    return sorted({mc_run_file(nu, G, seed, "large") for _, nu, G in mc_scale_points() for seed in MC["large_seeds"]})


def fig3_finite_files():
    """The finite-size prediction of each Monte Carlo run of Fig. 3 (the best single aggregate of
    its number of particles at its nu), against which its snapshot states its final energy."""
    sparse_nus = {MC["fiber_scan_nu"], *MC["nu_scan_nu"], MC["extra_seed_point"][1]}
    return sorted({finite_aggregate_file(MC["n"], nu) for nu in sparse_nus}
                  | {finite_aggregate_file(MC["dense_n"], MC["disk_scan_nu"])})


def finite_aggregate_files():
    """The finite-size predictions figX_mc_finite_size compares its runs with."""
    nus = {MC["fiber_scan_nu"], *MC["large_nu_scan_nu"]}
    return [finite_aggregate_file(n, nu) for n in (MC["n"], MC["large_n"]) for nu in sorted(nus)]


# Triangular particles (Fig. S6): settings, the nu grid of their diagram, their files.
TRIANGLE = config["triangle"]
TRIANGLE_MC = dict(TRIANGLE["montecarlo"], ell=TRIANGLE["ell"], eps=TRIANGLE["eps"])
TRIANGLE_NU = sorted({round(min(float(x), TRIANGLE["nu_max"]), 4) for x in np.linspace(0, 1, TRIANGLE["nu_count"])})


def triangle_catalogue_file(ell, nu):
    return f"results/triangle/catalogue/ell{float(ell):g}_nu{float(nu):g}.npz"


def triangle_finite_files():
    """The finite-size prediction of each box of Fig. S6's Monte Carlo runs (the best single
    aggregate of as many triangles, at the runs' nu)."""
    m = TRIANGLE_MC
    return [f"results/triangle/finite/n{int(n)}_nu{float(nu):g}.npz"
            for n, nu in ((m["n"], m["top_nu"]), (m["dense_n"], m["bottom_nu"]))]


def triangle_run_files():
    """Fig. S6d snapshots: the top row (sparse box) and the bottom row (dense box)."""
    m = TRIANGLE_MC
    runs = [("sparse", m["top_nu"], G) for G in m["top_Gamma"]]
    runs += [("dense", m["bottom_nu"], G) for G in m["bottom_Gamma"]]
    return [f"results/triangle/runs/{kind}_nu{float(nu):g}_G{float(G):g}.npz" for kind, nu, G in runs]


# Random-elasticity particles: the sample is drawn in batches; the aggregation diagrams of the
# selected particles (the 'sizes' set and one set per ell group) are computed a batch per job.
RANDOM = config["random"]
RANDOM_BATCHES = range(-(-RANDOM["draws"] // RANDOM["batch"]))
RANDOM_SETS = {"sizes": RANDOM["size_particles"]} | {f"group{i}": c for i, c in enumerate(RANDOM["group_counts"])}


def random_diagram_files(name):
    return [f"results/random/diagrams/{name}_{b}.npz" for b in range(-(-RANDOM_SETS[name] // RANDOM["diagram_batch"]))]


# The fixed-size Monte Carlo validation (montecarlo.smk, issue 33 item 1).
VALIDATION = MC["validation"]
VALIDATION_STEPS = {"fibre": "fibre_width_offsets", "disk": "disk_size_factors"}


def validation_points():
    """(scan, nu, Gamma) of the fixed-size validation: a fibre and a disk scan per Gamma."""
    return [(scan, VALIDATION[f"{scan}_nu"], G) for scan in VALIDATION_STEPS for G in VALIDATION["Gamma"]]


def validation_point_file(scan, nu, Gamma):
    return f"results/montecarlo/validation/{scan}_nu{float(nu):g}_G{float(Gamma):g}/point.json"


def validation_sample_files():
    return [validation_point_file(scan, nu, G).replace("point.json", f"size{k}_seed{seed}.json")
            for scan, nu, G in validation_points() for k in range(len(VALIDATION[VALIDATION_STEPS[scan]]))
            for seed in VALIDATION["seeds"]]


def validation_two_sided_files():
    """The two-sided checks (issue 33, item 4): per configured point and competitor, every seed."""
    return [validation_point_file(c["scan"], c["nu"], c["Gamma"]).replace(
                "point.json", f"two_sided_{c['competitor']}_seed{seed}.json")
            for c in VALIDATION["two_sided"] for seed in VALIDATION["seeds"]]


# The grand-canonical samples (montecarlo.smk, issue 33 item 2): one fibre per temperature,
# chemical potential and seed.
GRAND = VALIDATION["grand"]


def grand_sample_files():
    folder = f"results/montecarlo/validation/grand_nu{float(GRAND['nu']):g}_G{float(GRAND['Gamma']):g}"
    return [f"{folder}/T{t}_mu{m}_seed{seed}.json" for t in range(len(GRAND["temperatures_over_g"]))
            for m in range(len(GRAND["mu_offsets_over_g"])) for seed in GRAND["seeds"]]
