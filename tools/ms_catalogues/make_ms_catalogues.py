r"""Write springbalance's standard stock catalogues MS24585 and MS24586 (SI units) from ODOP's tables.

Source: the machine-readable copies of the standards in the MIT-licensed ODOP project
(https://github.com/thegrumpys/odop, commit ``d1cfc85120db84e981f4c46d2b007f28c3324472``, files
``client/src/designtypes/Spring/{Compression,Extension}/MS2458*_(SAE-AS2458*)_*.json``, last
changed in ODOP commit 8679f81e). They are copied unchanged, with ODOP's licence, in
``tools/ms_catalogues/odop/``. Run from the repository root:

    PYTHONPATH=src python tools/ms_catalogues/make_ms_catalogues.py   # rewrites src/springbalance/data/catalogues/

The tables (inches, pounds-force) give per part: outer diameter ``OD``, wire ``d``, total coils
``N_t``, and free length ``L_0`` (MS24585, closed and ground ends) or initial tension ``F_i``
(MS24586, full hooks); material music wire (ASTM A228, the ``_stl`` tables, dash numbers
``-1`` …) or 302 stainless (ASTM A313, the ``_ss`` tables, dash numbers ``C1`` …, "C" for
corrosion resistant). Conversion: 1 in = 0.0254 m and 1 lbf = 4.4482216152605 N (both exact by
definition). Each row becomes a catalogue row of :mod:`springbalance.io.catalogue`:

- mean diameter ``D = OD − d``; material ``music_wire`` or ``stainless_302``
  (:data:`springbalance.springs.materials.MATERIALS`);
- MS24585 (compression, closed and ground): active coils ``n = N_t − 2``, solid length
  ``L_s = d N_t`` (ODOP's ``Closed&Ground`` end type; the project's ``d (n + 2)``), free length
  ``L_0`` from the table, no initial tension, ``max_length = L_0``, ``min_length = L_s``;
- MS24586 (extension, full hooks): active coils ``n = N_t`` (the project's machine-hook model:
  body ``d (n + 1)``, free length ``d (n + 1) + 2 (D − d)`` with the hooks, the same as ODOP's
  ``L_Free`` for ``Full_Hook``; ODOP adds 0.4 coil of hook deflection to the rate, which the
  project's coil model does not, a rate 0.4/(N_t + 0.4) lower, at most 4.5 %), ``F_i`` from the
  table, ``min_length = l0``;
- rate ``k = G d⁴/(8 D³ n)`` with the project's ``G`` (81.0 GPa music wire, 69.0 GPa 302
  stainless; ODOP's tables use 11.5 and 10.0 Mpsi, 79.3 and 68.9 GPa);
- largest load: the smallest of the loads at which the project's static rules bind (Shigley
  Tables 10-6, 10-7): body stress ``K_B 8 F D/(π d³)`` at its allowable fraction of ``S_ut(d)``,
  and for extension springs the hook bending and torsion stresses at theirs; a compression part
  also at most its load at solid ``k (L_0 − L_s)``. An extension part's longest length is
  ``l0 + (F_max − F_i)/k``. (The standards publish their own loads; ODOP's copy does not carry
  them, so these are the project's rules, not the standard's ratings.)

Fixes of the copy (each checked by :func:`fixes`): the dash numbers run 1, 2, … in table order;
ODOP's copy repeats ``56`` and ``283`` in MS24585 (rows 57 and 263) and ``352`` in MS24586 steel
(row 353), so a row's dash number is its position. A part whose largest load does not exceed its
initial tension (it could never stretch within the rules) is left out and listed in the header.
"""

from __future__ import annotations

import argparse
import io
import json
import math
from pathlib import Path

from springbalance.springs.helical_formulas import (
    bergstrasser_factor,
    hook_bending_stress,
    hook_torsion_stress,
    spring_rate,
)
from springbalance.springs.materials import MATERIALS, Material

HERE = Path(__file__).resolve().parent
SOURCE = HERE / "odop"
ROOT = HERE.parents[1]
OUT = ROOT / "src" / "springbalance" / "data" / "catalogues"
ODOP_COMMIT = "d1cfc85120db84e981f4c46d2b007f28c3324472"
INCH = 0.0254  # [m], exact
POUND_FORCE = 4.4482216152605  # [N], exact
MATERIAL = {"MUSIC_WIRE": "music_wire", "302_STAINLESS": "stainless_302"}
#: standard → (kind, ODOP end type, [(ODOP file, dash-number prefix)])
STANDARDS = {
    "MS24585": (
        "compression",
        "Closed&Ground",
        [("MS24585_(SAE-AS24585)_c_stl.json", "-"), ("MS24585_(SAE-AS24585)_c_ss.json", "C")],
    ),
    "MS24586": (
        "extension",
        "Full_Hook",
        [("MS24586_(SAE-AS24586)_e_stl.json", "-"), ("MS24586_(SAE-AS24586)_e_ss.json", "C")],
    ),
}
#: (file, row position) → the name ODOP's copy gives it, where that is not the position
FIXES = {
    ("MS24585_(SAE-AS24585)_c_stl.json", 57): "56",
    ("MS24585_(SAE-AS24585)_c_stl.json", 263): "283",
    ("MS24585_(SAE-AS24585)_c_ss.json", 57): "C56",
    ("MS24585_(SAE-AS24585)_c_ss.json", 263): "C283",
    ("MS24586_(SAE-AS24586)_e_stl.json", 353): "352",
}
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
    "outer_diameter",
    "total_coils",
    "end_type",
    "source_row",
)


def fixes(name: str, rows: list[list], prefix: str) -> list[str]:
    """The dash number of each row (its position), after checking that ODOP's name is the position
    except at the known :data:`FIXES`."""
    numbers = []
    for position, row in enumerate(rows, start=1):
        expected = f"{'C' if prefix == 'C' else ''}{position}"
        if row[0] != expected and FIXES.get((name, position)) != row[0]:
            raise SystemExit(f"{name} row {position}: named {row[0]!r}, expected {expected!r}")
        numbers.append(expected)
    unused = [key for key in FIXES if key[0] == name and rows[key[1] - 1][0] != FIXES[key]]
    if unused:
        raise SystemExit(f"{name}: fixes {unused} no longer apply")
    return numbers


def max_load(kind: str, material: Material, d: float, D: float, k: float, free: float, solid: float) -> float:
    """The largest force [N] within the static rules (module docstring)."""
    strength = float(material.tensile_strength(d))  # S_ut [Pa]
    body = material.allowable_fraction[kind] * strength * math.pi * d**3 / (8 * bergstrasser_factor(D / d) * D)
    loads = [body]
    if kind == "extension":
        loads.append(material.hook_fraction["bending"] * strength / float(hook_bending_stress(1.0, d, D)))
        loads.append(material.hook_fraction["torsion"] * strength / float(hook_torsion_stress(1.0, d, D)))
    else:
        loads.append(k * (free - solid))
    return min(loads)


def rows_of(standard: str) -> tuple[list[dict], list[str]]:
    """The catalogue rows of ``standard`` and the parts left out (with why)."""
    kind, end_type, files = STANDARDS[standard]
    rows, left_out = [], []
    for name, prefix in files:
        table = json.loads((SOURCE / name).read_text(encoding="utf-8"))
        header, body = table[0], table[1:]
        for number, row in zip(fixes(name, body, prefix), body):
            cells = dict(zip(header, row))
            assert cells["End_Type"] == end_type, (name, row)
            material = MATERIALS[MATERIAL[cells["Material_Type"]]]
            d = cells["Wire_Dia"] * INCH
            outer = cells["OD_Free"] * INCH
            D = outer - d
            total = float(cells["Coils_T"])
            if kind == "compression":
                n, free, solid, tension = total - 2.0, cells["L_Free"] * INCH, d * total, 0.0
            else:
                n, tension = total, cells["Initial_Tension"] * POUND_FORCE
                free = d * (n + 1) + 2 * (D - d)
                solid = free
            k = float(spring_rate(material.shear_modulus, d, D, n))
            load = max_load(kind, material, d, D, k, free, solid)
            part = f"{standard}{'-' if prefix == '-' else ''}{number}"
            if kind == "extension" and load <= tension:
                left_out.append(f"{part} (largest load {load:.3g} N ≤ initial tension {tension:.3g} N)")
                continue
            if kind == "compression" and solid >= free:
                left_out.append(f"{part} (solid length {solid:.4g} m ≥ free length {free:.4g} m)")
                continue
            longest = free + (load - tension) / k if kind == "extension" else free
            rows.append(
                {
                    "part_number": part,
                    "type": kind,
                    "material": material.name,
                    "wire_diameter": d,
                    "mean_diameter": D,
                    "active_coils": n,
                    "free_length": free,
                    "initial_tension": tension,
                    "rate": k,
                    "max_load": load,
                    "max_length": longest,
                    "min_length": solid if kind == "compression" else free,
                    "outer_diameter": outer,
                    "total_coils": total,
                    "end_type": "closed_and_ground" if kind == "compression" else "full_hook",
                    "source_row": f"{name}:{row[0]}",
                }
            )
    return rows, left_out


def catalogue_text(standard: str) -> str:
    """The CSV text of ``<standard>.csv`` (lower case)."""
    rows, left_out = rows_of(standard)
    kind = STANDARDS[standard][0]
    stream = io.StringIO()
    stream.write(
        f"# {standard} helical {kind} springs (music wire {standard}-n, 302 stainless {standard}Cn), SI units:\n"
        "# m, N, N/m. Dimensions from the machine-readable copy of the standard in ODOP (MIT licence,\n"
        f"# LICENSE-ODOP.txt), https://github.com/thegrumpys/odop commit {ODOP_COMMIT};\n"
        "# rate and largest load computed with springbalance's material rules. Written by\n"
        "# tools/ms_catalogues/make_ms_catalogues.py (its docstring says how). Columns: docs/guides/coils-and-stock.md.\n"
    )
    if left_out:
        stream.write(f"# left out ({len(left_out)}): {'; '.join(left_out)}\n")
    stream.write(",".join(COLUMNS) + "\n")
    for row in rows:
        cells = [row[column] if isinstance(row[column], str) else f"{row[column]:.10g}" for column in COLUMNS]
        stream.write(",".join(cells) + "\n")
    return stream.getvalue()


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(OUT), help=f"directory of the CSV files (default {OUT})")
    args = parser.parse_args(argv)
    out = Path(args.out)
    for standard in STANDARDS:
        path = out / f"{standard.lower()}.csv"
        text = catalogue_text(standard)
        path.write_text(text, encoding="utf-8")
        print(f"wrote {sum(1 for line in text.splitlines() if line and not line.startswith('#')) - 1} parts to {path}")


if __name__ == "__main__":
    main()
