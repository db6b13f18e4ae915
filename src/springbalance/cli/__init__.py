"""The ``springbalance`` command-line tool.

::

    springbalance design CONFIG.yaml --out design.json [--starts N] [--seed S] [--method M] [--workers W] [--stock CATALOGUE.csv] [--quiet]
    springbalance evaluate design.json [--workspace WORKSPACE.yaml]
    springbalance clearance design.json [--samples N] [--radius R] [--margin M]
    springbalance view design.json [--port P] [--open] [--frames N]
    springbalance report design.json --out FOLDER [--no-scene]
    springbalance order design.json --out FOLDER [--grade G] [--finish TEXT] [--partial]
    springbalance export design.json [--urdf OUT.urdf] [--mjcf OUT.xml] [--resolve-packages]
    springbalance payload-range design.json --body BODY [--point X Y Z] [--masses M ...] [--max-residual R] [--plot PATH]
    springbalance robots [--paths]
    springbalance inspect ROBOT_OR_URDF [--json] [--mimic]
    springbalance schema [--out config.schema.json]

Every command takes ``--max-memory SIZE`` (e.g. ``2G``; default: the environment variable
``SPRINGBALANCE_MAX_MEMORY``, else half the available memory): work whose estimated memory is
larger (a workspace of too many samples, a scene of too many frames) is refused before it starts
(:mod:`springbalance.model.budget`).

Exit status: 0 on success, 1 when the solver finds no feasible design, 2 on bad input
(unknown key, body or joint, malformed file, missing file, too little memory, ...). Errors are printed as one
line, ``springbalance: error: <message>``, on stderr, without a traceback; ``design``
writes its output file atomically and only after a successful solve, so a failed run
leaves no (partial) output file behind.

The package: :mod:`~springbalance.cli.app` (:func:`main`, :func:`run`), :mod:`~springbalance.cli.parser`
(:func:`build_parser`), one module per command (``design``, ``evaluate``, ``clearance``, ``view``,
``report``, ``order``, ``export``, ``payload_range``, ``robots``, ``inspect``, ``explore``, ``schema``), each adding its
own parser and handler, and :mod:`~springbalance.cli.formatting` (the text: errors, tables, the
``inspect`` summary, the message of an interrupted design).
"""

from __future__ import annotations

from springbalance.cli.app import main, run
from springbalance.cli.formatting import MAX_STARTS_SHOWN, PROG
from springbalance.cli.parser import build_parser

__all__ = ["MAX_STARTS_SHOWN", "PROG", "build_parser", "main", "run"]
