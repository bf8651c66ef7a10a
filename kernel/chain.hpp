// The one-dimensional toy model of the paper (main text Eq. 1): a row of n trapezoids whose
// top (yellow) and bottom (red) faces are springs of stiffness k and rest lengths 1 +- eps,
// joined by connecting springs of stiffness kc/2 and rest length eps.
#pragma once

#include "minimize.hpp"

namespace pyfrustrate {

struct ChainParameters {
    int n;       // number of particles (n + 1 corners on each face)
    double k;    // face spring stiffness
    double kc;   // connecting spring stiffness (each particle has two springs of kc/2)
    double eps;  // mismatch: faces rest at 1 + eps (top) and 1 - eps (bottom)
    void validate() const;
};

// Energy of Eq. (1) summed over the n particles; x = (x_up[0..n], x_down[0..n]).
// Writes dE/dx into `gradient`.
double chain_energy(const ChainParameters& p, const Vector& x, Vector& gradient);

// Relaxes the chain from the bulk reference (all particles rectangles of width 1).
MinimizeResult chain_relax(const ChainParameters& p, const MinimizeOptions& options);

}  // namespace pyfrustrate
