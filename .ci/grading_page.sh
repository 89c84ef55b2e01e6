#!/usr/bin/env bash
# The course page's grading commands (docs/guide/course.md, section "Grading"), run as written in a fresh
# shell (`env -i`: no venv, no PATH entry but the system's, no IFSLIB_DATA but the one the page exports),
# from this checkout, with one student, alice. The page leaves two steps to the instructor, which this
# script does in their place: handing out and collecting (alice hands in the release unanswered), and
# `nbgrader formgrader` (a server that waits for a person: left out). Everything else is the page's text.
set -euo pipefail
cd "$(dirname "$0")/.."
make setup-grading
rm -rf mycourse
page=$(mktemp)
trap 'rm -f "$page"; rm -rf mycourse' EXIT
{
    echo 'set -euxo pipefail'
    # the fenced bash block of the Grading section, its comments kept (bash ignores them)
    awk '/^## Grading/ {on = 1} on && /^```bash/ {inside = 1; next} inside && /^```/ {exit} inside' \
        docs/guide/course.md | while IFS= read -r line; do
        case "$line" in
            "nbgrader formgrader"*) echo "# (formgrader waits for a person) $line" ;;
            *) echo "$line" ;;
        esac
        case "$line" in
            "nbgrader db student add alice"*)
                echo 'mkdir -p submitted/alice && cp -r release/lecture* submitted/alice/  # hand out, collect' ;;
        esac
    done
    echo 'test -n "$(ls feedback/alice/lecture1/*.html)"'
} > "$page"
grep -q '^nbgrader autograde' "$page" || { echo "no grading commands found in docs/guide/course.md" >&2; exit 1; }
env -i HOME="$HOME" PATH=/usr/local/bin:/usr/bin:/bin bash "$page"
echo "the course page's grading commands ran as written"
