"""The tests import the installed package (`pip install ./python`), never the source
folder `python/kisstime` (which lacks the compiled extension): `python -m pytest` run from
`python/` would otherwise put that folder first on the path."""

import pathlib
import sys

_SOURCE = pathlib.Path(__file__).resolve().parents[1]
sys.path[:] = [p for p in sys.path if pathlib.Path(p or ".").resolve() != _SOURCE]
