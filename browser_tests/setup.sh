#!/bin/sh
# Install what the browser tests need: Debian's Chromium and the playwright Python package.
# Fast when both are there. Never runs `playwright install` (the tests drive /usr/bin/chromium).
# Usage: sh browser_tests/setup.sh   (from the repository root, as root for apt-get; PY=... for another venv)
set -eu
PY=${PY:-.venv/bin/python}
CHROMIUM=${IFSLIB_CHROMIUM:-/usr/bin/chromium}

if [ ! -x "$CHROMIUM" ]; then
    if [ "$(id -u)" -ne 0 ]; then
        echo "Chromium is missing at $CHROMIUM; as root run: apt-get update && apt-get install -y chromium" >&2
        exit 1
    fi
    apt-get update
    DEBIAN_FRONTEND=noninteractive apt-get install -y chromium
fi

if ! "$PY" -c "import playwright.sync_api" 2>/dev/null; then
    "$PY" -m pip install --quiet playwright
fi

"$CHROMIUM" --version 2>/dev/null || true
"$PY" -c "import importlib.metadata as m; print('playwright', m.version('playwright'))"
