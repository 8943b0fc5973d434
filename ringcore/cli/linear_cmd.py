"""``ringcore linear``: characteristic numbers of the exact linear theory."""
from __future__ import annotations

import json
import math

from .. import linear
from .common import add_ring_arguments, ring_params_from_args


def register(sub) -> None:
    p = sub.add_parser("linear", help="linear theory summary (Q0, lambda_J, lambda_zero, max growth, beta_c, F2, F3)",
                       description="Exact linear theory of Eq. (17) for one parameter set.")
    add_ring_arguments(p)
    p.add_argument("--json", action="store_true", help="print one JSON object instead of text")
    p.set_defaults(func=run)


def _m(x):
    return "none" if x is None or (isinstance(x, float) and not math.isfinite(x)) else f"{x:.2f} m"


def run(args) -> int:
    p = ring_params_from_args(args)
    s = linear.summary(p)
    if args.json:
        print(json.dumps(s.to_json_dict()))
        return 0
    band = ", ".join(f"{a:.1f} m .. {'inf' if not math.isfinite(b) else f'{b:.1f} m'}"
                     for a, b in s.overstable_band_m) or "none"
    rows = [
        ("parameter set", f"{s.set} ({s.model}, p_s = {s.p_s:.3g})"),
        ("sigma0", f"{s.sigma0:g} kg/m^2"),
        ("Q0", "inf (no self-gravity)" if not math.isfinite(s.Q0) else f"{s.Q0:.4f}"),
        ("lambda_J", _m(s.lambda_J_m)),
        ("lambda_zero", _m(s.lambda_zero_m)),
        ("fastest-growing wavelength", _m(s.lambda_max_growth_m)),
        ("max growth rate", f"{s.max_growth_rate:.5g} Omega ({s.max_growth_rate * 2 * math.pi:.4g} e-folds/orbit)"),
        ("overstable band", band),
        ("beta_c (exact long-wave)", f"{s.beta_c:.4f}"),
        ("beta_c (approx., Eq. (21))", f"{s.beta_c_approx:.4f}"),
        ("F2, F3 (exact)", f"{s.F2:.4f}, {s.F3:.4f}"),
        ("F2, F3 (table)", f"{s.F2_table:.2f}, {s.F3_table:.2f}" if math.isfinite(s.F2_table) else "-"),
    ]
    w = max(len(a) for a, _ in rows)
    for a, b in rows:
        print(f"{a:<{w}}  {b}")
    return 0
