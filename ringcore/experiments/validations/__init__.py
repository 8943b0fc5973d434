"""Long validations of the engines against independent answers (``ringcore validate NAME``).

Each module provides ``HELP`` (one line), ``add_arguments(parser)`` and ``run(args) -> int`` (exit
status 0 if every check passes, 1 otherwise; the printed table is the record).  They take minutes
to hours and are not part of the test suite; quick versions of the same checks are.
"""
VALIDATIONS = ("hydro-linear", "nbody-groundstate", "nbody-linear", "nbody-impacts")


def modules() -> dict:
    """``{name: module}`` of every validation, in :data:`VALIDATIONS` order (imported here, on demand: each
    loads an engine)."""
    from . import hydro_linear, nbody_groundstate, nbody_impacts, nbody_linear

    return {"hydro-linear": hydro_linear, "nbody-groundstate": nbody_groundstate, "nbody-linear": nbody_linear,
            "nbody-impacts": nbody_impacts}
