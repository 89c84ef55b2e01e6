"""The exercises' harness: run a student's function with the library's own switched off (`run_answer`), and read
an answer as a matrix or a number; each raises ``AssertionError`` with a hint."""
from __future__ import annotations

import contextlib
import functools
import importlib
import math
import sys
import threading
import types
from typing import Callable, Iterator

import numpy as np

from ... import threads as _threads  # noqa: F401 - before torch loads (ifslib.threads)
import torch  # noqa: E402
from ...errors import IFSError
from .library import ALLOWED, LIBRARY


class WriteItYourself(RuntimeError):
    """Raised by a library function that a test has switched off (``name``: the function reached): write your own."""

    def __init__(self, name: str = "a library function"):
        super().__init__(f"{name} is switched off while this test runs: write it yourself")
        self.name = name


# What is switched off now, with how many `library_off` blocks hold it: key -> [restore, count].
# A function switched off by two blocks at once (nested, or from two threads) is restored when the
# last one ends, whatever the order they end in; the lock keeps the swaps of two threads apart.
_LOCK = threading.RLock()
_ACTIVE: dict[tuple, list] = {}


def _owner(module_name: str, path: str) -> tuple[object, str]:
    """The module or class that holds ``path`` (``attribute`` or ``Class.attribute``), and the attribute."""
    owner = importlib.import_module(module_name)
    *outer, attr = path.split(".")
    for name in outer:
        owner = getattr(owner, name)
    return owner, attr


def _stored(owner, attr: str):
    """What ``owner`` keeps under ``attr``, as it was before any switch-off: a class's property or method itself."""
    entry = _ACTIVE.get(("attr", id(owner), attr))
    if entry is not None:
        return entry[2]
    if isinstance(owner, type):
        for klass in owner.__mro__:
            if attr in vars(klass):
                return vars(klass)[attr]
    return getattr(owner, attr)


def _functions(value) -> list[types.FunctionType]:
    """The plain Python functions behind ``value``: itself, a property's accessors, a static or class
    method's function, and what each wraps (``__wrapped__``)."""
    if isinstance(value, property):
        parts = [value.fget, value.fset, value.fdel]
    elif isinstance(value, (staticmethod, classmethod)):
        parts = [value.__func__]
    else:
        parts = [value]
    out, seen = [], set()
    for part in parts:
        while part is not None and id(part) not in seen:
            seen.add(id(part))
            if isinstance(part, types.FunctionType):
                out.append(part)
            part = getattr(part, "__wrapped__", None)
    return out


def _is_plain(value) -> bool:
    """Whether switching off ``value``'s functions' code switches ``value`` off wherever it is held."""
    if isinstance(value, property):
        return all(f is None or isinstance(f, types.FunctionType) for f in (value.fget, value.fset, value.fdel))
    if isinstance(value, (staticmethod, classmethod)):
        return isinstance(value.__func__, types.FunctionType)
    return isinstance(value, types.FunctionType)


@functools.lru_cache(maxsize=None)
def _raising_code(free: tuple[str, ...], name: str) -> types.CodeType:
    """Code that raises `WriteItYourself` naming ``name``, with the free variables ``free`` of the function
    whose ``__code__`` it replaces (a function's closure must match its code's free variables)."""
    lines = ["def _outer():"] + [f"    {v} = None" for v in free] + ["    def _off(*args, **kwargs):"]
    if free:
        lines.append(f"        ({', '.join(free)},)")
    lines += [f"        raise __import__({__name__!r}, fromlist=['_']).WriteItYourself({name!r})", "    return _off"]
    scope: dict = {}
    exec(compile("\n".join(lines), f"<{name} switched off>", "exec"), scope)  # noqa: S102  our own text
    return scope["_outer"]().__code__


def _hold(key: tuple, switch: Callable[[], Callable[[], None]], keep: object = None) -> tuple:
    """Switch off what ``key`` names (``switch`` does it and returns the restore) unless it is off already."""
    entry = _ACTIVE.get(key)
    if entry is None:
        entry = _ACTIVE[key] = [switch(), 0, keep]
    entry[1] += 1
    return key


def _code_off(function: types.FunctionType, name: str) -> tuple:
    def switch():
        original = function.__code__
        function.__code__ = _raising_code(original.co_freevars, name)
        return lambda: setattr(function, "__code__", original)
    return _hold(("code", id(function)), switch, function)


def _attribute_off(owner, attr: str, name: str) -> tuple:
    def switch():
        own = attr in vars(owner)
        original = vars(owner)[attr] if own else getattr(owner, attr)
        off = _switched_off(name)
        setattr(owner, attr, property(off) if isinstance(original, property) else off)
        return (lambda: setattr(owner, attr, original)) if own else (lambda: delattr(owner, attr))
    return _hold(("attr", id(owner), attr), switch, _stored(owner, attr))


def _global_off(namespace: dict, key: str, name: str) -> tuple:
    def switch():
        original = namespace[key]
        namespace[key] = _switched_off(name)
        return lambda: namespace.__setitem__(key, original)
    return _hold(("global", id(namespace), key), switch, namespace)


def _release(keys: list[tuple]) -> None:
    for key in reversed(keys):
        entry = _ACTIVE[key]
        entry[1] -= 1
        if entry[1] == 0:
            del _ACTIVE[key]
            entry[0]()


def _switched_off(name: str) -> Callable:
    def off(*args, **kwargs):
        raise WriteItYourself(name)
    off.__name__ = f"{name.rsplit('.', 1)[-1]}_switched_off"
    return off


def _originals(exercise: str, imported: bool = False) -> list[tuple[object, str, object, str]]:
    """(owner, attribute, what it keeps, dotted name) for each of ``exercise``'s library functions (``imported``: of
    modules already imported)."""
    if exercise not in LIBRARY:
        raise KeyError(f"no exercise {exercise!r}; one of {sorted(LIBRARY)}")
    out = []
    for module_name, path in LIBRARY[exercise]:
        if imported and (module_name not in sys.modules
                         or path.split(".")[0] not in vars(sys.modules[module_name])):
            continue
        try:
            owner, attr = _owner(module_name, path)
            value = _stored(owner, attr)
        except (ImportError, AttributeError):   # a route that this version lacks: nothing to switch off
            continue
        out.append((owner, attr, value, f"{module_name}.{path}"))
    return out


@contextlib.contextmanager
def library_off(exercise: str, answer: Callable | None = None) -> Iterator[None]:
    """Within the block, the library's functions for ``exercise`` raise `WriteItYourself`, wherever they are held: a
    function's ``__code__`` is swapped, a builtin replaced; restored when the block ends (the lock: nested blocks)."""
    keys: list[tuple] = []
    with _LOCK:
        try:
            saved = _originals(exercise)
            others = {}
            for owner, attr, value, name in saved:
                keys += [_code_off(f, name) for f in _functions(value)]
                if not _is_plain(value):   # a builtin: replaced where it is kept, and in the answer's globals
                    keys.append(_attribute_off(owner, attr, name))
                    others[id(value)] = name
            namespace = getattr(_unwrapped(answer), "__globals__", None)
            if isinstance(namespace, dict) and others:
                keys += [_global_off(namespace, k, others[id(v)]) for k, v in list(namespace.items())
                         if id(v) in others]
        except BaseException:
            _release(keys)
            raise
    try:
        yield
    finally:
        with _LOCK:
            _release(keys)


def _unwrapped(answer):
    """The function under ``functools.partial``, ``functools.wraps`` wrappers and bound methods."""
    seen = set()
    while id(answer) not in seen:
        seen.add(id(answer))
        if isinstance(answer, (functools.partial, functools.partialmethod)):
            answer = answer.func
        elif hasattr(answer, "__wrapped__"):
            answer = answer.__wrapped__
        elif hasattr(answer, "__func__"):
            answer = answer.__func__
    return answer


def _library_functions() -> dict[int, str]:
    """id -> dotted name of every function of `LIBRARY` (of the modules imported so far)."""
    with _LOCK:
        held = [(value, name) for exercise in LIBRARY for _, _, value, name in _originals(exercise, imported=True)]
    return {id(v): name for value, name in held for v in [value, *_functions(value)]}


def _held_library(answer) -> str | None:
    """The library function that ``answer`` is, wraps, or holds (a closure, frozen or default arguments): its
    dotted name, or None. Any function of ifslib's own counts."""
    library = _library_functions()
    inner = _unwrapped(answer)
    for candidate in (answer, inner):
        if id(candidate) in library:
            return library[id(candidate)]
    module = str(getattr(inner, "__module__", "") or "")
    if module.startswith("ifslib"):
        return f"{module}.{getattr(inner, '__qualname__', '?')}"
    cells = getattr(inner, "__closure__", None) or ()
    frozen = [getattr(answer, "args", ()), tuple(getattr(answer, "keywords", {}).values()),
              getattr(inner, "__defaults__", None) or (),
              tuple((getattr(inner, "__kwdefaults__", None) or {}).values())]
    held = [cell.cell_contents for cell in cells if _filled(cell)] + [v for group in frozen for v in group]
    for value in held:
        for candidate in (value, _unwrapped(value)):
            if id(candidate) in library:
                return library[id(candidate)]
    return None


def _filled(cell) -> bool:
    try:
        cell.cell_contents
    except ValueError:
        return False
    return True


class _Watch:
    """While a student's function runs, a profile hook refuses every call into ifslib outside ``allowed``, by module
    however it was reached; a refusal is recorded, so catching it (or removing the hook) still fails."""

    def __init__(self, allowed: frozenset[str]):
        self.allowed = allowed
        self.refused: list[str] = []

    def __call__(self, frame, event, arg):
        if event == "call":
            module = frame.f_globals.get("__name__") or ""
            # "ifslib" itself only resolves its lazy names (a module's attribute), which are watched in turn
            if module.startswith("ifslib.") and not self._allows(module):
                name = f"{module}.{frame.f_code.co_name}"
                self.refused.append(name)
                raise WriteItYourself(name)
        elif event == "c_call" and arg in _PROFILE_SETTERS and frame.f_code is not _Watch.__exit__.__code__:
            self.refused.append(f"sys.{getattr(arg, '__name__', 'setprofile')}")
            raise WriteItYourself("sys.setprofile")

    def _allows(self, module: str) -> bool:
        return module in self.allowed or any(module.startswith(a + ".") for a in self.allowed)

    def __enter__(self):
        self.before = sys.getprofile()
        sys.setprofile(self)
        threading.setprofile(self)
        return self

    def __exit__(self, *exc):
        intact = sys.getprofile() is self
        sys.setprofile(self.before)
        threading.setprofile(None)
        if not intact:
            self.refused.append("the check's watch (sys.setprofile)")
        return False


_PROFILE_SETTERS = (sys.setprofile, sys.settrace, threading.setprofile, threading.settrace)


def run_answer(answer, exercise: str, *args):
    """The student's ``answer(*args)`` with the library's own off and the rest of ifslib refused (`_Watch`), as `plain`
    values; ``AssertionError`` with a hint otherwise."""
    assert answer is not None and answer is not Ellipsis, f"write your {exercise} first (the cell above)."
    assert callable(answer), (f"give your function itself (its name, without brackets), "
                              f"got {type(answer).__name__}.")
    _kernel_check()
    held = _held_library(answer)
    assert held is None, f"that is {held.split('.')[0]}'s own function ({held}); write the {exercise} yourself."
    watch = _Watch(ALLOWED.get(exercise, frozenset()) | {"ifslib.errors", __package__})
    try:
        with library_off(exercise, answer), watch:
            result = answer(*args)
    except WriteItYourself as off:
        raise _calls_library(off.name, exercise) from None
    except AssertionError:
        raise
    except Exception as exc:  # noqa: BLE001  a student's bug is answered with a hint, not torch's traceback
        if watch.refused:
            raise _calls_library(watch.refused[0], exercise) from None
        raise AssertionError(f"your function raised {type(exc).__name__}: {exc}") from None
    if watch.refused:
        raise _calls_library(watch.refused[0], exercise)
    return plain(result, f"your {exercise}")


def _calls_library(name: str, exercise: str) -> AssertionError:
    whose, short = name.split(".")[0], name.rsplit(".", 1)[-1]
    return AssertionError(f"your function calls {whose}'s own {short} ({name}), directly or through another "
                          f"function: write the {exercise} yourself (numpy and scipy's building blocks are fine).")


#: Exact types a test reads as they are; a subclass (which may redefine ``==``) is refused.
_NUMBERS = (bool, int, float, np.bool_, np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint16, np.uint32,
            np.uint64, np.float16, np.float32, np.float64)


_SCANNED: dict = {}


def _kernel_check() -> None:
    """Say at once what the grader will not trust in the cells run so far in this IPython kernel (`integrity.scan`,
    each cell read once)."""
    try:
        from IPython import get_ipython
    except ImportError:
        return
    shell = get_ipython()
    history = getattr(shell, "user_ns", {}).get("_ih") if shell is not None else None
    if not history:
        return
    from .integrity import scan

    modules = frozenset({k for k, v in shell.user_ns.items() if isinstance(v, types.ModuleType)}
                        | {"np", "torch", "ifslib", "math"})
    for k, source in enumerate(history):
        key = (source, modules)
        if source and key not in _SCANNED:
            # a lesson's own imports (io, pathlib) are the lesson's: `scan` leaves imports to the grader
            _SCANNED[key] = scan([(f"[{k}]", source)], modules)
        if source and _SCANNED[key]:
            raise AssertionError(f"{_SCANNED[key][0]}: the grader does not trust a notebook that does this and "
                                 "gives the tests after that cell no points; take it out and run the notebook again.")


def plain(value, name: str = "your answer"):
    """``value`` as plain data a test can compare without trusting it; ``AssertionError`` for anything else, a subclass
    included (it can answer ``==`` with anything)."""
    from ...core.geometry.ifs import IFS

    _kernel_check()
    kind = type(value)
    if value is None or kind is IFS:
        return value
    if kind in _NUMBERS:
        return value.item() if isinstance(value, np.generic) else value
    if kind is str:
        return value
    if kind in (tuple, list):
        return kind(plain(v, name) for v in value)
    if kind is dict:
        return {plain(k, name): plain(v, name) for k, v in value.items()}
    if kind is np.ndarray:
        assert value.dtype.kind in "biuf", f"{name}: give numbers, got an array of {value.dtype}."
        return np.array(value, dtype=bool if value.dtype.kind == "b" else float)
    if kind in (torch.Tensor, torch.nn.Parameter):
        return value.as_subclass(torch.Tensor) if kind is torch.nn.Parameter else value
    raise AssertionError(f"{name}: give plain numbers, strings, lists, tuples, dicts or arrays, "
                         f"got {kind.__module__}.{kind.__qualname__}.")


def as_matrix(answer, shape: tuple[int, ...], name: str) -> np.ndarray:
    """``answer`` (a list, array or tensor) as a float64 array of ``shape``; ``AssertionError`` with a hint otherwise."""
    assert answer is not None and answer is not Ellipsis, f"{name}: write your answer first."
    assert not callable(answer), f"{name}: give the numbers themselves, not a function."
    answer = plain(answer, name)
    try:
        value = np.asarray(answer.detach().numpy() if isinstance(answer, torch.Tensor) else answer, dtype=float)
    except (TypeError, ValueError):
        raise AssertionError(f"{name}: give a {shape} array of numbers, got {type(answer).__name__}.") from None
    assert value.shape == tuple(shape), f"{name}: give a {tuple(shape)} array, got shape {value.shape}."
    assert np.isfinite(value).all(), f"{name}: your array holds values that are not finite numbers."
    return value


def as_number(answer, name: str) -> float:
    """``answer`` (an int, a float or a one-number array or tensor) as a finite float; ``AssertionError`` otherwise."""
    answer = plain(answer, name)
    if isinstance(answer, torch.Tensor) and answer.numel() == 1:
        answer = answer.item()
    elif isinstance(answer, np.ndarray) and answer.size == 1:
        answer = answer.item()
    assert not isinstance(answer, bool) and isinstance(answer, (int, float, np.integer, np.floating)), \
        f"{name}: give one number, got {type(answer).__name__}."
    assert math.isfinite(float(answer)), f"{name}: give a finite number, got {answer}."
    return float(answer)


def random_maps(rng: np.random.Generator, m: int, lo: float = 0.3, hi: float = 0.55,
                shear: float = 0.0) -> np.ndarray:
    """Random affine contractions ``(m, 3, 3)`` for a test's inputs: a rotation, scales in ``[lo, hi]`` (``hi < 1``), a
    shear up to ``shear``, a translation; a linear part the shear stretches beyond ``hi`` is scaled back to it."""
    if not 0 < lo <= hi < 1:
        raise IFSError(f"random_maps needs 0 < lo <= hi < 1 for contractions, got lo={lo}, hi={hi}")
    out = np.zeros((m, 3, 3))
    for i in range(m):
        a = rng.uniform(-math.pi, math.pi)
        rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        lin = rot @ np.diag(rng.uniform(lo, hi, 2)) @ np.array([[1.0, rng.uniform(-shear, shear)], [0.0, 1.0]])
        largest = np.linalg.svd(lin, compute_uv=False)[0]
        if largest > hi:
            lin = lin * (hi / largest)
        out[i, :2, :2], out[i, :2, 2], out[i, 2, 2] = lin, rng.uniform(-0.3, 0.3, 2), 1.0
    return out
