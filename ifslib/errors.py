"""The one exception type that ifslib raises for bad input (a `ValueError`), its message naming what is at fault."""


class IFSError(ValueError):
    """A bad IFS, file, argument or request (the message says which and why)."""


#: The largest seed a fit takes: torch seeds with at most ``2**64 - 1``, and the strategies add a run's index.
MAX_SEED = 2**63 - 1


def check_int(value, name: str, minimum: int, hint: str = "", maximum: int | None = None) -> int:
    """Return ``value`` if it is an int (not a bool) >= ``minimum`` (and <= ``maximum``, when given), else raise `IFSError`."""
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise IFSError(f"{name} must be an integer >= {minimum}{hint}, got {value!r}")
    if maximum is not None and value > maximum:
        raise IFSError(f"{name} must be an integer from {minimum} to {maximum:,}{hint}, got {value!r}")
    return value


def check_positive(value, name: str, unit: str = "") -> float:
    """Return ``value`` as a float if it is a finite real number > 0 (not a bool), else raise `IFSError`."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = float("nan")
    if isinstance(value, bool) or not (number > 0 and number != float("inf")):
        raise IFSError(f"{name} must be a finite number{unit} > 0, got {value!r}")
    return number


class LeafBudgetError(IFSError):
    """More leaves than the leaf budget allows (the message says how many, and what to change)."""
