# Names shared by the rules: the nu grid of the ansatz diagrams and the catalogue file of a particle.
ANSATZ = config["ansatz"]
DIAGRAM_NU = sorted({round(min(float(x), ANSATZ["nu_max"]), 4) for x in np.linspace(0, 1, ANSATZ["nu_count"])})


def catalogue_file(ell, nu):
    return f"results/ansatz/catalogue/ell{float(ell):g}_nu{float(nu):g}.npz"
