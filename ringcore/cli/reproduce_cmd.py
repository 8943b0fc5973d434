"""``ringcore reproduce NAME --quick|--full`` and ``ringcore reproduce --list``."""
from __future__ import annotations

import contextlib
import json

from ..experiments.registry import get_recipe, load_all, outputs
from ..io import reserve_output
from ..paperlabels import to_published
from ..paperrefs import ref
from .common import refuse_with
from .safety import FILE_INCREMENT, check_new_files, check_output_dir
from . import threads_opt


def register(sub) -> None:
    p = sub.add_parser("reproduce", help="re-run a figure of the paper as a named recipe",
                       description="Each recipe writes OUT/NAME.png (with a caption of what was run) and "
                                   "OUT/NAME.nc; existing ones are kept unless --overwrite.")
    p.add_argument("name", nargs="?", help="recipe name (see --list)")
    p.add_argument("--list", action="store_true", help="list recipes with the paper's figure (or section) numbers and costs")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--quick", dest="mode", action="store_const", const="quick",
                   help="reduced box / fewer orbits, same physics (default)")
    g.add_argument("--full", dest="mode", action="store_const", const="full", help="the paper's settings (hours)")
    p.add_argument("--out", default="reproduce-out", help="output folder (default reproduce-out)")
    p.add_argument("--overwrite", action="store_true", help="replace OUT/NAME.png and OUT/NAME.nc if they exist")
    p.add_argument("--json", action="store_true",
                   help="print the result (or with --list the recipes) as one JSON object")
    threads_opt.add(p)
    p.set_defaults(func=run, mode="quick")


def run(args) -> int:
    recipes = load_all()
    if args.list or args.name is None:
        if args.list:
            refuse_with(args, ("name", "mode", "out", "overwrite"), "with --list (it only lists the recipes)")
        if args.json:  # the published number for readers; the LaTeX label for scripts that matched it
            print(json.dumps({n: {"figure": ref(recipes[n].figure), "label": recipes[n].figure,
                                  "title": to_published(recipes[n].title), "quick_cost": recipes[n].quick_cost,
                                  "full_cost": recipes[n].full_cost} for n in sorted(recipes)}))
            return 0
        w = max(len(n) for n in recipes)
        print(f"{'name':<{w}}  {'paper':<13} {'quick':>8} {'full':>10}  title")
        for n in sorted(recipes):
            r = recipes[n]
            print(f"{n:<{w}}  {ref(r.figure):<13} {r.quick_cost:>8} {r.full_cost:>10}  {to_published(r.title)}")
        return 0
    recipe = get_recipe(args.name)
    files = outputs(args.name, args.out)
    check_output_dir(args.out, size=len(files) * FILE_INCREMENT)  # at least 64 KiB per file (figure, data)
    check_new_files(files, overwrite=args.overwrite, label=f"reproduce {args.name}")
    with contextlib.ExitStack() as held:  # both outputs are this run's until it ends (a second run is refused)
        for f in files:
            f.parent.mkdir(parents=True, exist_ok=True)
            held.enter_context(reserve_output(f, overwrite=bool(args.overwrite), label="--out"))
        res = recipe.run(args.mode, args.out, overwrite=bool(args.overwrite))  # atomic; no-clobber unless --overwrite
    if args.json:
        print(json.dumps({"name": args.name, "mode": args.mode, "seconds": res.seconds, "figure": str(res.png),
                          "data": str(res.data), "caption": res.caption}))
        return 0
    print(f"{args.name} ({args.mode}): {res.seconds:.1f} s\n  figure: {res.png}\n  data:   {res.data}\n  {res.caption}")
    return 0
