"""The one exception type that ifslib raises for bad input.

`IFSError` subclasses `ValueError`, so ``except ValueError`` keeps working; every message names the
field, index or value at fault.
"""


class IFSError(ValueError):
    """A bad IFS, file, argument or request (the message says which and why)."""
