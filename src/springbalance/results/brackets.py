"""``long_bracket``: an anchor that stands far off its link, so that a build needs a bracket the design leaves out.

A spring with an anchor on a moving link farther than :data:`BRACKET_WARNING` from that link's collision
geometry gets one warning (:func:`long_bracket_flags`) with each such bracket's shortest length ``d`` [m] (to
the nearest surface point, :mod:`springbalance.model.brackets`), the spring's largest tension ``F`` [N] over
the workspace and the moment ``F·d`` [N·m] it puts on the longest bracket's root. Where such a bracket's straight
line passes through another link at one of the workspace's poses (up to :data:`BRACKET_POSES` of them, evenly
spread), the warning says which link and how deep: the bracket must go round it. The brackets' mass and stiffness
are not in the design. Anchors on the ground, and arms without collision geometry, get none.
"""

from __future__ import annotations

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.model.brackets import bracket_crossings, spring_brackets
from springbalance.results.flag import Flag

#: an anchor farther than this [m] from its link's surface gets a ``long_bracket`` warning (a stand-off, an eye
#: bolt or a clevis reaches about this far; beyond it the bracket is a part to design)
BRACKET_WARNING = 0.05
#: at most this many of the workspace's poses (evenly spread) are checked for a bracket through another link
BRACKET_POSES = 256


def long_bracket_flags(result: EvaluatedDesign) -> list[Flag]:
    """One ``long_bracket`` warning per spring with an anchor farther than :data:`BRACKET_WARNING` from its link."""
    problem, records = result.problem, result.springs
    far = {
        key: held for key, held in spring_brackets(problem.mechanism, records).items() if held.length > BRACKET_WARNING
    }
    configurations = problem.base_workspace.configurations
    chosen = np.unique(np.linspace(0, len(configurations) - 1, min(len(configurations), BRACKET_POSES)).astype(int))
    crossings = bracket_crossings(problem.mechanism, far, configurations[chosen])
    tensions = np.asarray(result.evaluation.tensions)
    found = []
    for column, record in enumerate(records):
        name = record["name"]
        ends = [(end, far[(name, end)]) for end in ("a", "b") if (name, end) in far]
        if not ends:
            continue
        force = float(np.max(np.abs(tensions[:, column]))) if tensions.size else 0.0
        stands = ", ".join(f"{end} stands {1e3 * held.length:.0f} mm off {held.body}" for end, held in ends)
        through = [
            f"the straight bracket at {end} passes through {crossings[(name, end)].link} at some poses "
            f"({1e3 * crossings[(name, end)].depth:.0f} mm deep) and must go round it"
            for end, _ in ends
            if (name, end) in crossings
        ]
        found.append(
            Flag(
                "long_bracket",
                name,
                f"spring {name!r} needs a bracket at each far anchor ({stands}), carrying up to {force:.0f} N, "
                f"{force * max(held.length for _, held in ends):.1f} N·m at the longest one's root"
                + "".join(f"; {text}" for text in through)
                + "; the brackets' mass and stiffness are not in the design",
                "mount such an anchor on its link (on: collision, offset: 0.02) or bring its box nearer the link; "
                "a bracket that stays must be designed for that load and checked against the other links",
            )
        )
    return found
