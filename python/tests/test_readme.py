"""Every Python example of README.md and python/README.md runs as written, and prints what
the page shows under it (a ```text block right after it; a line ``…`` stands for any lines,
a line ending in ``…`` for any line that starts with what precedes it). The examples of a
page run in order in one namespace, from a folder that holds the repository's ``examples/``
and ``data/`` as a clone does. (The shell examples: tests/readme.rs.)"""

import contextlib
import io
import os
import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
FENCE = re.compile(r"^```(\w*)\s*$")


def blocks(text):
    """(lang, lines, follows) per fenced block; ``follows`` when only blank lines separate
    it from the block before."""
    out, current, blank_gap = [], None, False
    for line in text.splitlines():
        m = FENCE.match(line.strip())
        if current is not None:
            if line.strip().startswith("```"):
                out.append(current)
                current, blank_gap = None, True
            else:
                current[1].append(line)
        elif m:
            current = (m.group(1), [], blank_gap and bool(out))
        elif line.strip():
            blank_gap = False
    assert current is None, "an unclosed code block"
    return out


def shows(shown, actual):
    """None when ``actual`` (lines) is what ``shown`` shows, else what differs."""

    def ok(e, a):
        return a.rstrip().startswith(e[:-1]) if e.endswith("…") else e.rstrip() == a.rstrip()

    i = j = 0
    while i < len(shown):
        if shown[i].strip() == "…":
            i += 1
            if i == len(shown):
                return None
            while j < len(actual) and not ok(shown[i], actual[j]):
                j += 1
            if j == len(actual):
                return f"no line shows {shown[i]!r}"
        if j >= len(actual) or not ok(shown[i], actual[j]):
            return f"shown {shown[i]!r}, got {actual[j] if j < len(actual) else None!r}"
        i += 1
        j += 1
    if j < len(actual):
        return f"more output than shown, from {actual[j]!r}"
    return None


def test_the_matcher_can_fail():
    assert shows(["a", "…", "c…"], ["a", "x", "c 1"]) is None
    assert shows(["a", "…", "c…"], ["a", "x"]) is not None
    assert shows(["a"], ["a", "b"]) is not None
    assert shows(["a"], ["b"]) is not None


@pytest.mark.parametrize("page", ["README.md", "python/README.md"])
def test_the_python_examples_run_as_written(page, tmp_path, monkeypatch):
    for sub in ("examples", "data"):
        os.symlink(ROOT / sub, tmp_path / sub)
    monkeypatch.chdir(tmp_path)
    bs = blocks((ROOT / page).read_text(encoding="utf-8"))
    namespace = {"__name__": "__readme__"}
    ran = 0
    for k, (lang, lines, _) in enumerate(bs):
        if lang != "python":
            continue
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile("\n".join(lines), f"{page} block {k}", "exec"), namespace)
        ran += 1
        if k + 1 < len(bs) and bs[k + 1][0] == "text" and bs[k + 1][2]:
            diff = shows(bs[k + 1][1], out.getvalue().splitlines())
            assert diff is None, f"{page}, example {ran}: {diff}\n--- output:\n{out.getvalue()}"
    assert ran >= 3, f"{page} has {ran} Python examples"
