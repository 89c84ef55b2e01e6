"""Command line: ``python -m ifslib render | fit | info | compress | decompress`` (also installed as ``ifslib``).

Examples::

    python -m ifslib render koch --size 512 --depth 6 -o koch.png
    python -m ifslib fit target.png --pattern koch --steps 1500 -o fitted.json
    python -m ifslib info fitted.json
    python -m ifslib compress photo.png -o photo.ifsc --bpp 0.25
    python -m ifslib decompress photo.ifsc -o photo.png --scale 2
    python -m ifslib --version

A command's result goes to standard output; progress goes to standard error, as live bars on a
terminal and as one line per stage in a log (`ifslib.progress`). Exit codes: see `EXIT_CODES`.
"""
from __future__ import annotations

import argparse
import sys
import textwrap
from pathlib import Path

import numpy as np


#: What ``python -m ifslib`` exits with (printed by ``--help``).
EXIT_CODES = {
    0: "success",
    1: "a file could not be read or written (one line on standard error), or an unexpected error "
       "(a traceback: please report it)",
    2: "bad arguments or bad input: an unknown option, a missing file, an invalid IFS or image "
       "(one line on standard error)",
    130: "interrupted (Ctrl-C)",
}


def _spec(value: str):
    """An IFS from a JSON file or a pattern name."""
    from . import load_ifs, patterns

    if value.endswith(".json") or Path(value).is_file():
        return load_ifs(value)
    return patterns.by_name(value)


def _save_png(image: np.ndarray, path: str) -> None:
    from PIL import Image

    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray((np.clip(image, 0, 1) * 255).round().astype(np.uint8), mode="L").save(path)


def _depth(value: str) -> int | str:
    """``--depth``: an integer K, or ``attractor``."""
    if value == "attractor":
        return value
    try:
        return int(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer or 'attractor', got {value!r}") from None


def cmd_render(args: argparse.Namespace) -> None:
    from . import render
    from .errors import IFSError

    ifs = _spec(args.spec)
    depth = args.depth
    if args.window is not None and depth is None:
        depth = "attractor"
    if args.window is not None and depth != "attractor":
        raise IFSError("--window draws the attractor: leave out --depth (or say --depth attractor)")
    if args.chaos is not None:
        if depth not in (None, "attractor"):
            raise IFSError("--chaos draws the attractor: leave out --depth (or say --depth attractor)")
        image = render(ifs, args.size, sigma=args.sigma, method="chaos", points=args.chaos, seed=args.seed,
                       window=args.window)
        what = f"the attractor by the chaos game ({args.chaos:,} points, seed {args.seed})"
    elif depth == "attractor":
        image = render(ifs, args.size, depth, args.sigma, window=args.window, tolerance=args.tolerance)
        what = f"the attractor (within {args.tolerance:g} px)"
    else:
        depth = ifs.depth if depth is None else depth
        image = render(ifs, args.size, depth, args.sigma)
        what = f"depth {depth}, {ifs.n_leaves(depth):,} leaves"
    _save_png(image.detach().cpu().numpy(), args.output)
    window = "" if args.window is None else f", window {tuple(args.window)}"
    print(f"wrote {args.output}: {args.size}x{args.size}{window}, {what}")


def _stage_text(stage) -> str:
    """``256² 120`` for a stage of a drawing, ``256² attractor 80`` for one of the attractor."""
    return f"{stage.size}²{' attractor' if stage.depth == 'attractor' else ''} {stage.steps}"


def _stages_text(history) -> str:
    """One line on how a strategy spent its steps (the pyramid's starts and stages, the automatic pattern's choice,
    and for a figure fitted both as a fractal and as a shape, which kind was kept)."""
    text = _spent_text(history)
    decision = None if history.auto is None else history.auto.decision
    return text if decision is None else f"{text}; fitted as a fractal and as a shape: {decision}"


def _spent_text(history) -> str:
    stages, auto = history.stages, history.auto
    if auto is not None and auto.kind == "fractal":
        tried = ", ".join(f"{c.maps} maps{' (the learned guess)' if c.by == 'learned score' else ''} score {c.value:.3f}"
                          for c in auto.candidates)
        return (f"{history.cost} steps spent (auto: a fractal, {auto.chosen} maps chosen by the search's rule, "
                f"1 - attractor IoU plus a cost per map ({tried}); then "
                f"{', '.join(_stage_text(s) for s in stages)} steps)")
    if auto is not None:
        tried = ", ".join(f"{c.maps} maps {c.value:.3g}" for c in auto.candidates)
        runs = ", ".join(_stage_text(s) for s in stages)
        return (f"{history.cost} steps spent (auto: a {auto.kind}, {auto.chosen} maps chosen by the loss "
                f"after {auto.candidates[0].steps} steps at {stages[0].size}² ({tried}); then {runs} steps)")
    if not stages:
        return f"{history.cost} steps spent ({history.strategy or 'plain'})"
    last = max(s.start for s in stages)
    runs = ", ".join(_stage_text(s) for s in stages if s.start == last)
    verdict = "recovered the target" if history.recovered else "was the best"
    return (f"{history.cost} steps spent (pyramid: start {last + 1} of the {history.starts_tried} tried "
            f"{verdict}; its stages: {runs} steps)")


def _fit_options(args: argparse.Namespace):
    """The run's settings from ``args``, checked (`RunOptions`: the loss's name among them) with the strategy's name;
    with ``--pattern auto`` and a ``--loss`` named, standard error says where the automatic path uses it."""
    from .automatic.config import AUTO
    from .core.fitting.options import with_settings
    from .core.fitting.strategies import check_strategy
    from .core.scoring.losses import DEFAULT_LOSS

    if args.strategy is not None:
        check_strategy(args.strategy)
    named = {"lr": args.lr, "loss": DEFAULT_LOSS if args.loss is None else args.loss, "tol": args.tol,
             "depth": "attractor" if args.depth == "attractor" else None}
    options = with_settings(None, named)
    if args.pattern == "auto" and args.loss is not None:
        print(f"--loss {args.loss}: the automatic path probes and climbs a curve's or a shape's candidates with it; "
              f"a fractal's maps are fitted with the {AUTO.fit.fractal_loss} loss, and a shape's last stage with "
              f"{AUTO.fit.polish_loss}", file=sys.stderr)
    return options


def cmd_fit(args: argparse.Namespace) -> None:
    import time

    from . import evaluate, fit, initialize, load_target, save_ifs
    from .automatic.plan import discover
    from .errors import IFSError
    from .core.fitting.options import Checkpoint

    t0 = time.perf_counter()
    options = _fit_options(args)  # every name checked before the image is read or a search starts
    target = load_target(args.target, args.size, invert=args.invert)
    if not args.quiet:
        # a fit of the background must never be silent: say which part is the figure, and how to take the other
        print(f"target: {target.polarity}; {'--no-invert' if target.inverted else '--invert'} to fit the other part",
              file=sys.stderr)
    attractor = args.depth == "attractor"  # fit the attractor at every stage, not only the last
    if args.pattern == "auto":
        if attractor:
            raise IFSError("--depth attractor goes with a pattern: an automatic start compares depths of its own "
                           "and its fit ends on the attractor anyway")
        chosen = {} if args.learned is None else {"learned": args.learned}   # else the automatic path's own default
        start = discover(target, args.maps, args.depth, jitter=args.jitter, seed=args.seed, **chosen)
    else:
        if args.maps is not None or args.learned is not None:
            raise IFSError(f"{'--maps' if args.maps is not None else '--learned'} goes with --pattern auto")
        ifs = _spec(args.pattern)
        if args.depth is not None and not attractor:
            ifs.depth = args.depth
        start = initialize(ifs, target, jitter=args.jitter, seed=args.seed)
    if args.strategy == "splat":
        from . import splatting  # noqa: F401 - an extension's strategy is in the core's table once it is imported
    saved = None if args.checkpoint is None and args.resume is None else Checkpoint(args.checkpoint,
                                                                                   resume=args.resume)
    result = fit(start, target, steps=args.steps, strategy=args.strategy, seed=args.seed, progress=not args.quiet,
                 checkpoint=saved, options=options)
    m = evaluate(result.best, target)
    result.best.meta["target"] = {"polarity": target.polarity, "inverted": target.inverted}
    result.best.meta["scores"] = {
        "depth": {"depth": result.best.depth, **{k: m[k] for k in ("iou", "f1", "chamfer")}},
        "attractor": {k: m[f"attractor_{k}"] for k in ("iou", "f1", "chamfer")}}
    save_ifs(result.best, args.output)
    print(f"wrote {args.output}: best loss {result.best_loss:.4g}; attractor: IoU {m['attractor_iou']:.3f}, "
          f"F1 {m['attractor_f1']:.3f}, Chamfer {m['attractor_chamfer']:.2f} px; drawn at depth {result.best.depth}: "
          f"IoU {m['iou']:.3f}, F1 {m['f1']:.3f}, Chamfer {m['chamfer']:.2f} px"
          + (f"; {len(result.history.rollbacks)} rolled-back steps" if result.history.rollbacks else "")
          + f"; {_stages_text(result.history)}; {time.perf_counter() - t0:.1f} s")


def cmd_info(args: argparse.Namespace) -> None:
    from .core.geometry.leaves import leaf_count_text
    from .core.geometry.rules import singular_values
    import torch  # after ifslib's folders: they set torch's threads and OpenMP's wait policy first

    ifs = _spec(args.spec)
    depth = ifs.depth if args.depth is None else args.depth
    print(repr(ifs))
    maps = ifs.maps().detach().double()
    smallest, scales = singular_values(maps)  # the contraction is the largest (IFS.scales)
    for i, (rule, t, s, lo) in enumerate(zip(ifs.rules, maps, scales, smallest)):
        # a similarity stretches every direction alike; an affine map has two singular values
        shape = f" (singular values {s:.4f}, {lo:.4f}{', reflects' if torch.det(t[:2, :2]) < 0 else ''})" \
            if rule.kind == "affine" else ""
        print(f"rule {i}: {rule.kind} {list(rule.source)} -> {list(rule.target)}  contraction {s:.4f}{shape}")
        print(f"  [[{t[0, 0]: .4f} {t[0, 1]: .4f} {t[0, 2]: .4f}]\n   [{t[1, 0]: .4f} {t[1, 1]: .4f} {t[1, 2]: .4f}]]")
    _print_measure(ifs)
    print(f"leaves at depth {depth}: {leaf_count_text(ifs, depth)}")


def _print_measure(ifs) -> None:
    """``info``'s lines on the measure and the dimension: the probabilities (whose) and Moran's root."""
    from .errors import IFSError
    from .measures.dimension import ifs_scales, similarity_dimension

    p = ifs.measure_probabilities().tolist()
    whose = "the file's" if ifs.probabilities is not None else "default: in proportion to |det|, with a floor"
    print(f"probabilities ({whose}): " + ", ".join(f"{x:.4f}" for x in p))
    scales, similar = ifs_scales(ifs)
    try:
        dimension = similarity_dimension(scales)
    except IFSError:
        print("similarity dimension: none (a map does not contract)")
        return
    if similar:
        print(f"similarity dimension (Moran's equation): {dimension:.4f} (the attractor's dimension when "
              "the copies do not overlap; at most that when they do)")
    else:
        print(f"similarity dimension: not defined, the maps are not similarities; Moran's equation with "
              f"their largest singular values gives {dimension:.4f}, an upper bound of the box dimension "
              "(itself at most 2 in the plane)")


def build_parser() -> argparse.ArgumentParser:
    codes = "\n".join(textwrap.fill(text, 96, initial_indent=f"  {code:<4} ", subsequent_indent=" " * 7)
                      for code, text in EXIT_CODES.items())
    parser = argparse.ArgumentParser(
        prog="python -m ifslib", formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Differentiable iterated function systems: render an IFS, fit one to an image, or describe one; "
                    "fractal-compress a photograph.",
        epilog="progress: live bars on standard error when it is a terminal; otherwise one line per stage.\n"
               f"exit codes:\n{codes}\n\n`python -m ifslib COMMAND --help` describes a command's options.")
    parser.add_argument("--version", action=_Version, nargs=0, help="show the versions of ifslib, torch and Python, and exit")
    sub = parser.add_subparsers(dest="command", required=True, metavar="{render,fit,info,compress,decompress}")
    _render_parser(sub)
    _fit_parser(sub)
    _info_parser(sub)
    from .cli_compress import add_parsers

    add_parsers(sub)
    return parser


def _render_parser(sub) -> None:
    """``render``'s options."""
    r = sub.add_parser("render", help="render an IFS (JSON file or pattern name) to a PNG")
    r.add_argument("spec", help="an ifslib/1 JSON file, or a pattern: koch, koch_paper, carpet, fern, gridN, rosetteN")
    r.add_argument("--size", type=int, default=512, help="pixels per side (default 512)")
    r.add_argument("--depth", type=_depth, help="recursion depth K, or 'attractor' for the attractor itself "
                   "(default: the file's depth)")
    r.add_argument("--window", type=float, nargs=4, metavar=("X0", "Y0", "X1", "Y1"),
                   help="draw this box of the plane (the frame is -0.5 -0.5 0.5 0.5) at full detail: the attractor")
    r.add_argument("--tolerance", type=float, default=0.5,
                   help="for the attractor: the distance is within this many pixels of the true one (default 0.5)")
    r.add_argument("--chaos", type=int, metavar="N", help="draw the attractor by the chaos game with N points")
    r.add_argument("--seed", type=int, default=0, help="seed of the chaos game (default 0)")
    r.add_argument("--sigma", type=float, help="line width in plane units (default: one pixel)")
    r.add_argument("-o", "--output", required=True, help="PNG file to write")
    r.set_defaults(run=cmd_render)


def _fit_parser(sub) -> None:
    """``fit``'s options."""
    from .names import DEFAULT_LOSS, DEFAULT_LR, DEFAULT_STEPS, LOSSES, STRATEGIES

    f = sub.add_parser("fit", help="fit an IFS pattern to a target image")
    f.add_argument("target", help="target image (its figure found from its border: the background is the colour "
                   "that touches it; a transparent background makes the opaque part the figure), or "
                   "koch/sierpinski/apple/flower")
    f.add_argument("--pattern", default="koch",
                   help="auto (any image: a fractal's maps searched for, a curve or a shape; the number of maps compared), koch, koch_paper, carpet, "
                        "gridN, rosetteN, or an ifslib/1 JSON file (default koch)")
    f.add_argument("--maps", type=int, help="with --pattern auto: this many maps instead of comparing candidates")
    f.add_argument("--learned", action=argparse.BooleanOptionalAction, default=None,
                   help="with --pattern auto: offer the learned first guess of a fractal's maps beside the search's, "
                        "the one whose attractor scores better kept (default: off, docs/results/learned-guess.md)")
    f.add_argument("--size", type=int, default=256, help="target size in pixels (default 256)")
    f.add_argument("--depth", type=_depth, help="render depth (default: the pattern's, 3), or 'attractor' to fit the "
                   "attractor at every stage (the default fits end on it anyway)")
    f.add_argument("--steps", type=int, default=DEFAULT_STEPS,
                   help=f"step budget of each run (default {DEFAULT_STEPS}, the paper's run); the default strategy stops each "
                        "stage once its loss has converged")
    f.add_argument("--tol", type=float, default=None,
                   help="early stop: end a run when its best loss improved by at most this fraction over the last "
                        "steps (default: the strategy's; off for plain)")
    f.add_argument("--lr", type=float, default=DEFAULT_LR, help=f"learning rate (default {DEFAULT_LR:g}, as the paper)")
    f.add_argument("--loss", default=None, choices=LOSSES, metavar="LOSS",
                   help=f"{', '.join(LOSSES)} (default {DEFAULT_LOSS}, as the library's)")
    f.add_argument("--jitter", type=float, default=0.0, help="uniform jitter of the initial points (plane units)")
    f.add_argument("--seed", type=int, default=0, help="seed of the jitter and the run")
    f.add_argument("--invert", action=argparse.BooleanOptionalAction, default=None,
                   help="--invert: the figure is the target's dark (or transparent) part; --no-invert: its light "
                        "(or opaque) part (default: found from the image's border, and said on standard error)")
    f.add_argument("--checkpoint", help="write a resumable checkpoint here every 100 steps")
    f.add_argument("--resume", help="continue from this checkpoint")
    f.add_argument("--strategy", default=None, choices=STRATEGIES, metavar="STRATEGY",
                   help="pyramid (the default: coarse to fine in pixels, starts tried until one recovers the "
                        "target; a single run with --checkpoint/--resume; auto for --pattern auto), plain (one run, the paper's), multistart, "
                        "coarse_to_fine, restart, anneal, uncross, or splat (the start's maps and probabilities fitted on "
                        "the differentiable chaos game; the start kept when it scores better)")
    f.add_argument("--quiet", action="store_true",
                   help="no progress output (by default: live bars on a terminal, one line per stage in a log)")
    f.add_argument("-o", "--output", required=True, help="JSON file for the fitted IFS")
    f.set_defaults(run=cmd_fit)


def _info_parser(sub) -> None:
    """``info``'s options."""
    i = sub.add_parser("info", help="print an IFS's maps, contraction factors, leaf count, probabilities and "
                                         "similarity dimension")
    i.add_argument("spec", help="an ifslib/1 JSON file, or a pattern name")
    i.add_argument("--depth", type=int, help="depth for the leaf count (default: the file's)")
    i.set_defaults(run=cmd_info)


class _Version(argparse.Action):
    """``--version``: torch's version is read only when asked for (importing torch takes a second)."""

    def __call__(self, parser, namespace, values, option_string=None):
        import torch

        from . import __version__

        print(f"ifslib {__version__} (torch {torch.__version__}, Python {sys.version.split()[0]})")
        parser.exit()


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status (`EXIT_CODES`: 0 done, 1 a file, 2 bad input, 130 Ctrl-C).

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program's name (``sys.argv[1:]`` when None).

    Returns
    -------
    int
        The exit status. Bad arguments exit through argparse with status 2 as well.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    from .errors import IFSError

    try:
        args.run(args)
    except IFSError as exc:
        print(f"ifslib {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"ifslib {args.command}: error: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"ifslib {args.command}: interrupted", file=sys.stderr)
        return 130
    return 0


if __name__ == "__main__":
    sys.exit(main())
