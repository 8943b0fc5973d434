"""Array layout shared by the compiled hydro kernels: ghost nodes, the rows of the scratch array, the
indices of the parameter vector, and the fast-math flags (:mod:`ringcore.hydro.kernels` re-exports them all).

Array layout (all C-contiguous float64)
---------------------------------------
``U``        (nv, N): conservative variables (sigma, sigma u, sigma v[, e]) with
             nv = 4 (non-isothermal) or 3 (isothermal), ``e = sigma (u^2/2 + 3T/2)``
             (Eq. (25)).  N = n + 2 NG: the n interior nodes are ``U[:, NG:NG+n]``,
             node j sits at x_j = -L_x/2 + j h; ``NG`` periodic ghost nodes on each side
             are refilled by the kernels themselves.

``W``        (NW, N): scratch rows (named ``R_*`` below), owned by the caller.

``beta``     (N,): viscosity exponent per node (buffer zones), ghosts included.

``g``        (n,): radial self-gravity force per unit mass -d(phi)/dx at interior nodes.

``par``      (NPAR,): plain floats, indices ``P_*`` below.
"""

NG = 6  # ghost nodes per side (MP5 and the 6th-order central differences need 3)

# rows of the scratch array W
R_U, R_V, R_T, R_P, R_C, R_ETA, R_GAM = 0, 1, 2, 3, 4, 5, 6
R_UX, R_VX, R_TX, R_UXX, R_VXX, R_TXX, R_ETAX = 7, 8, 9, 10, 11, 12, 13
R_DIF, R_SIG = 14, 15  # diffusivity and |u| + c for the time step
R_FP = 16  # 4 rows F+
R_FM = 20  # 4 rows F-
R_FH = 24  # 4 rows numerical flux f_{i+1/2} (stored at index i)
R_RATE = 28  # cooling relaxation rate (2/3) G_T Gamma/(sigma T) for the time step
R_MP5 = 29  # 4 scratch rows: MP5 reconstruction (mp5.NSCRATCH); log sigma, log T; the split pressures p+, p-
NW = 33

# indices into the parameter vector
P_NU0, P_KRATIO, P_T0, P_PS, P_PT, P_NT, P_GS, P_GT, P_GAMMA0, P_BULK, P_H = range(11)
P_DTMODE, P_DTFACTOR, P_GRAVITY = 11, 12, 13
NPAR = 14

_FM = {"nsz"}  # no contract/arcp/afn/reassoc: their use depends on inlining, and cached code
# would then differ in the last bits from freshly compiled code (breaks bit-for-bit restarts);
# no nnan/ninf: blow-ups stay visible
