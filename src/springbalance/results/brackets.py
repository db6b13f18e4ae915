"""``long_bracket``: an anchor that stands far off its link, so that a build needs a bracket the design leaves out.

A spring with an anchor on a moving link farther than :data:`BRACKET_WARNING` from that link's collision
geometry gets one warning (:func:`long_bracket_flags`) with each such bracket's shortest length ``d`` [m] (to
the nearest surface point, :mod:`springbalance.model.brackets`), the spring's largest tension ``F`` [N] over
the workspace and the moment ``F·d`` [N·m] it puts on the longest bracket's root. The bracket's mass, stiffness and clearance from the other
links are not in the design. Anchors on the ground, and arms without collision geometry, get none.
"""

from __future__ import annotations

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.model.brackets import spring_brackets
from springbalance.results.flag import Flag

#: an anchor farther than this [m] from its link's surface gets a ``long_bracket`` warning (a stand-off, an eye
#: bolt or a clevis reaches about this far; beyond it the bracket is a part to design)
BRACKET_WARNING = 0.05


def long_bracket_flags(result: EvaluatedDesign) -> list[Flag]:
    """One ``long_bracket`` warning per spring with an anchor farther than :data:`BRACKET_WARNING` from its link."""
    records = result.springs
    brackets = spring_brackets(result.problem.mechanism, records)
    tensions = np.asarray(result.evaluation.tensions)
    found = []
    for column, record in enumerate(records):
        name = record["name"]
        far = [(end, brackets[(name, end)]) for end in ("a", "b") if (name, end) in brackets]
        far = [(end, held) for end, held in far if held.length > BRACKET_WARNING]
        if not far:
            continue
        force = float(np.max(np.abs(tensions[:, column]))) if tensions.size else 0.0
        ends = ", ".join(f"{end} stands {1e3 * held.length:.0f} mm off {held.body}" for end, held in far)
        longest = max(held.length for _, held in far)
        found.append(
            Flag(
                "long_bracket",
                name,
                f"spring {name!r} needs a bracket at each far anchor ({ends}), carrying up to {force:.0f} N, "
                f"{force * longest:.1f} N·m at the longest one's root; their mass, stiffness and clearance are "
                "not in the design",
                "mount such an anchor on its link (on: collision, offset: 0.02) or bring its box nearer the link; "
                "a bracket that stays must be designed for that load and checked against the other links",
            )
        )
    return found
