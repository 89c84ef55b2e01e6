"""The paper's target images, resolved by name at run time (never committed): from ``IFSLIB_DATA``, else a cache
(``IFSLIB_CACHE``, default ``~/.cache/ifslib``) filled on first use from the paper's repository."""
from __future__ import annotations

import os
import tempfile
import urllib.error
import urllib.request
from pathlib import Path

from .errors import IFSError

NAMES = ("koch", "sierpinski", "apple", "flower")
BASE_URL = "https://raw.githubusercontent.com/cory-b-scott/diff_ifs/main/"


def path(name: str, base_url: str | None = None, timeout: float = 30.0) -> Path:
    """Local path of one of the paper's images (`NAMES`, with or without ``.png``), downloaded from ``base_url``
    (``$IFSLIB_DATA_URL`` or the paper's repository) when neither ``IFSLIB_DATA`` nor the cache holds it."""
    stem = name[:-4] if name.endswith(".png") else name
    if stem not in NAMES:
        raise IFSError(f"unknown image {name!r}; the paper's images are: {', '.join(NAMES)}")
    filename = f"{stem}.png"
    folder = os.environ.get("IFSLIB_DATA")
    if folder and (Path(folder) / filename).is_file():
        return Path(folder) / filename
    cached = Path(os.environ.get("IFSLIB_CACHE", Path.home() / ".cache" / "ifslib")) / filename
    if cached.is_file():
        return cached
    url = (base_url or os.environ.get("IFSLIB_DATA_URL") or BASE_URL).rstrip("/") + "/" + filename
    try:
        with urllib.request.urlopen(url, timeout=timeout) as response:
            payload = response.read()
    except (urllib.error.URLError, OSError) as exc:
        where = f"IFSLIB_DATA={folder!r} has no {filename}" if folder else "IFSLIB_DATA is not set"
        raise IFSError(f"cannot find {filename}: {where}, and downloading {url} failed ({exc}). Either set "
                       f"IFSLIB_DATA to a folder holding the paper's images, or allow the download.") from None
    cached.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=cached.parent, suffix=".part")
    with os.fdopen(fd, "wb") as fh:
        fh.write(payload)
    os.replace(tmp, cached)
    return cached

