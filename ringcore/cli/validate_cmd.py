"""``ringcore validate NAME``: the long validations of the engines (minutes to hours; not CI tests).

The validations live in :mod:`ringcore.experiments.validations`; each prints its table and exits
with status 1 if a check fails.
"""
from __future__ import annotations

from ringcore.experiments.validations import modules


def register(sub) -> None:
    p = sub.add_parser("validate", help="long validations of the engines against independent answers",
                       description="Long validations of the engines (not part of the test suite).")
    names = p.add_subparsers(dest="validation", metavar="NAME", required=True, parser_class=type(p))
    for name, mod in modules().items():
        q = names.add_parser(name, help=mod.HELP, description=mod.HELP)
        mod.add_arguments(q)
        q.set_defaults(func=mod.run)
