"""Regenerates this folder's tables from pooltool 0.6.0 (``kisstime.pooltool.table_json``).

    python data/tables/make_tables.py        # needs pooltool and the kisstime package

- ``7ft.json``: ``pt.Table.default()``, pooltool's default pocket table (its
  "7 Ft Showood", the table of 8-ball and 9-ball games), built into kisstime as ``7ft``;
- ``snooker.json``: ``pt.Table.from_game_type(GameType.SNOOKER)`` ("Generic Snooker");
- ``billiard.json``: ``pt.Table.from_game_type(GameType.THREECUSHION)`` (the carom table,
  no pockets).

The files are what ``table_json`` writes (floats with ``repr``: they read back exactly).
``python/tests/test_bridge.py`` checks that pooltool still gives them, and ``cargo test``
(``src/io/table_json.rs``) that kisstime's built-in ``7ft`` is ``7ft.json`` bit for bit and
that the snooker and billiard tables load.
"""

from pathlib import Path

import pooltool as pt
from pooltool.game.datatypes import GameType

from kisstime.pooltool import table_json

HERE = Path(__file__).resolve().parent

TABLES = {
    "7ft.json": lambda: pt.Table.default(),
    "snooker.json": lambda: pt.Table.from_game_type(GameType.SNOOKER),
    "billiard.json": lambda: pt.Table.from_game_type(GameType.THREECUSHION),
}


def main() -> None:
    for name, make in TABLES.items():
        (HERE / name).write_text(table_json(make()) + "\n", encoding="utf-8")
        print(f"wrote {HERE / name}")


if __name__ == "__main__":
    main()
