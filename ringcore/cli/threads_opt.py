"""``--threads N`` of the commands that run an engine: validated at once, then the default of every run the
command starts (:func:`ringcore.threads.set_default`, inherited by the worker processes it starts)."""
from __future__ import annotations

from .errors import UsageError


def add(p) -> None:
    """Add ``--threads N`` to the subcommand parser ``p``."""
    p.add_argument("--threads", default=None, metavar="N",
                   help="threads per run (default: the cores this process may use; the results are the same "
                        "bits for any number)")


def apply(args) -> None:
    """Validate ``args.threads`` (UsageError naming --threads and the allowed range) and make it the default."""
    value = getattr(args, "threads", None)
    if value is None:
        return
    from .. import threads  # imports numba: only when the option is given (ringcore info etc. start faster)

    hi = threads.maximum()
    try:
        n = int(str(value).strip())
    except ValueError:
        raise UsageError(f"--threads = {value!r} is not valid: give a whole number 1 <= N <= {hi}") from None
    if not 1 <= n <= hi:
        raise UsageError(f"--threads = {n} is out of range: allowed 1 <= N <= {hi} (the cores numba may use "
                         f"on this machine; this process may use {threads.available()})")
    threads.set_default(n)
