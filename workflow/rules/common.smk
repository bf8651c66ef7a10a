# Names shared by the rules: the nu grid of the ansatz diagrams and the catalogue file of a particle.
ANSATZ = config["ansatz"]
DIAGRAM_NU = sorted({round(min(float(x), ANSATZ["nu_max"]), 4) for x in np.linspace(0, 1, ANSATZ["nu_count"])})


def catalogue_file(ell, nu):
    return f"results/ansatz/catalogue/ell{float(ell):g}_nu{float(nu):g}.npz"

MC = config["montecarlo"]


def mc_run_file(nu, Gamma, seed, dense):
    kind = "dense" if dense else "sparse"
    return f"results/montecarlo/runs/{kind}_nu{float(nu):g}_G{float(Gamma):g}_seed{seed}.npz"


def mc_snapshot_files():
    """The runs of Fig. 3b: the fibre scan (nu fixed, Gamma rising), the dense disk scan (the
    bottom row), the nu scan at fixed Gamma, and every seed at the extra point."""
    first = MC["seeds"][0]
    runs = [(MC["fiber_scan_nu"], G, first, False) for G in MC["scan_Gamma"]]
    runs += [(MC["disk_scan_nu"], G, first, True) for G in MC["scan_Gamma"]]
    runs += [(nu, MC["nu_scan_Gamma"], first, False) for nu in MC["nu_scan_nu"]]
    G, nu = MC["extra_seed_point"]
    runs += [(nu, G, seed, False) for seed in MC["seeds"]]
    return sorted({mc_run_file(*r) for r in runs})
