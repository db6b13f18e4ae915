r"""Write examples/stock_springs.csv: an example stock catalogue computed from springbalance's own series.

These are computed parts of the project's standard series, NOT a vendor's catalogue: every row
is a music-wire (ASTM A228) coil spring worked out with the formulas and tables of
:mod:`springbalance.springs.sizing` (Shigley's *Mechanical Engineering Design*, ch. 10). Check
a real supplier's data before buying anything.

    python examples/make_stock_catalogue.py            # rewrites examples/stock_springs.csv
    python examples/make_stock_catalogue.py --out my.csv

The series (168 parts):

- wire diameters ``d``: the preferred sizes of ``PREFERRED_WIRE_DIAMETERS`` 0.8, 1.0, 1.2, 1.6,
  2.0, 2.5, 3.0 and 4.0 mm; material ``music_wire`` (``G`` = 81.0 GPa, ``S_ut = 2211 MPa / d^0.145``
  with d in mm); spring indices ``C = D/d`` of 6, 8 and 10 (mean coil diameter ``D = C d``);
- rate ``k = G d⁴/(8 D³ n)`` for every part;
- **extension springs** with machine hooks, ``n`` = 10, 20, 40 and 80 active coils:
  free length ``l0 = 2(D − d) + d(n + 1)`` (hooks plus the close-wound body, Shigley §10-11);
  initial tension in the middle of Shigley's preferred band (Eq. 10-40), ``τ_i = 231/exp(0.105 C)``
  MPa (the band is ± 6.9 (4 − (C − 3)/6.5) MPa), ``F_i = τ_i π d³/(8 D)``; maximum load at the
  allowable body stress, 45 % of ``S_ut`` (Table 10-7) with the Bergsträsser factor
  ``K_B = (4C + 2)/(4C − 3)``: ``F_max = 0.45 S_ut π d³/(8 K_B D)``; longest length
  ``max_length = l0 + (F_max − F_i)/k``; ``min_length = l0``. (The stresses in the hooks are not
  checked.)
- **compression springs** with squared-and-ground ends, ``n`` = 4, 8 and 16 active coils:
  pitch ``p = 0.4 D`` (a pitch angle of about 7°), free length ``l0 = p n + 2d`` and solid length
  ``L_s = d (n + 2)`` (Shigley Table 10-1); maximum load the smaller of the load at the allowable
  stress, 45 % of ``S_ut`` (Table 10-6) with ``K_B``, and the load at solid ``k (l0 − L_s)``;
  ``max_length = l0``, ``min_length = L_s``, no initial tension.

Lengths and diameters are written in metres to 1 µm, the rate is computed from the written
diameters and coils (so it matches ``G d⁴/(8 D³ n)`` exactly), forces to 1 mN.
"""

from __future__ import annotations

import argparse
import csv
import io
import math
from pathlib import Path

from springbalance.springs.sizing import MATERIALS, PREFERRED_WIRE_DIAMETERS, bergstrasser_factor, spring_rate

HERE = Path(__file__).resolve().parent
OUT = HERE / "stock_springs.csv"

MATERIAL = "music_wire"
WIRES_MM = (0.8, 1.0, 1.2, 1.6, 2.0, 2.5, 3.0, 4.0)
INDICES = (6, 8, 10)
EXTENSION_COILS = (10, 20, 40, 80)
COMPRESSION_COILS = (4, 8, 16)
PITCH_PER_MEAN_DIAMETER = 0.4  # compression springs: pitch p = 0.4 D
ALLOWABLE_FRACTION = 0.45  # of S_ut: extension body (Table 10-7) and compression (Table 10-6)
COLUMNS = (
    "part_number",
    "type",
    "material",
    "wire_diameter",
    "mean_diameter",
    "active_coils",
    "free_length",
    "initial_tension",
    "rate",
    "max_load",
    "max_length",
    "min_length",
)


def _m(value: float) -> float:
    """A length [m] to 1 µm."""
    return round(value, 6)


def _n(value: float) -> float:
    """A force [N] to 1 mN."""
    return round(value, 3)


def parts() -> list[dict]:
    """Every row of the catalogue, as mappings column → value."""
    material = MATERIALS[MATERIAL]
    G = material.shear_modulus  # [Pa]
    wires = [d for d in PREFERRED_WIRE_DIAMETERS if any(abs(d - w * 1e-3) < 1e-12 for w in WIRES_MM)]
    assert len(wires) == len(WIRES_MM), "every wire of the series is a preferred size"
    rows = []
    for kind, coils in (("extension", EXTENSION_COILS), ("compression", COMPRESSION_COILS)):
        for d in wires:
            allowable = ALLOWABLE_FRACTION * float(material.tensile_strength(d))  # [Pa]
            for C in INDICES:
                D = _m(C * d)
                K_B = bergstrasser_factor(C)
                stress_load = allowable * math.pi * d**3 / (8 * K_B * D)  # [N]
                for n in coils:
                    k = spring_rate(G, d, D, n)  # [N/m]
                    code = f"{'EXT' if kind == 'extension' else 'CMP'}-MW-d{d * 1e3:.1f}-C{C}-n{n}"
                    if kind == "extension":
                        free = _m(2 * (D - d) + d * (n + 1))
                        tau_i = 231e6 / math.exp(0.105 * C)  # [Pa], middle of the band
                        tension = _n(tau_i * math.pi * d**3 / (8 * D))  # [N]
                        load = _n(stress_load)
                        longest, shortest = _m(free + (load - tension) / k), free
                    else:
                        free = _m(PITCH_PER_MEAN_DIAMETER * D * n + 2 * d)
                        solid = _m(d * (n + 2))
                        tension = 0.0
                        load = _n(min(stress_load, k * (free - solid)))
                        longest, shortest = free, solid
                    rows.append(
                        {
                            "part_number": code,
                            "type": kind,
                            "material": MATERIAL,
                            "wire_diameter": d,
                            "mean_diameter": D,
                            "active_coils": n,
                            "free_length": free,
                            "initial_tension": tension,
                            "rate": k,
                            "max_load": load,
                            "max_length": longest,
                            "min_length": shortest,
                        }
                    )
    return rows


def catalogue_text() -> str:
    """The CSV text of examples/stock_springs.csv."""
    stream = io.StringIO()
    stream.write(
        "# Example stock catalogue of springbalance: computed parts of the project's own standard series,\n"
        "# not a vendor's catalogue. Generated by examples/make_stock_catalogue.py (its docstring says how).\n"
        "# Music wire (ASTM A228); SI units: m, N, N/m. Columns: docs/guides/coils-and-stock.md.\n"
    )
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow(COLUMNS)
    for row in parts():
        writer.writerow([row[column] if isinstance(row[column], str) else f"{row[column]:.7g}" for column in COLUMNS])
    return stream.getvalue()


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(OUT), help=f"where to write the CSV (default {OUT})")
    args = parser.parse_args(argv)
    Path(args.out).write_text(catalogue_text(), encoding="utf-8")
    print(f"wrote {len(parts())} parts to {args.out}")


if __name__ == "__main__":
    main()
