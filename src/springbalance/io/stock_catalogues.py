r"""The stock catalogues springbalance ships, and what a ``--stock`` (or ``solve: {stock: ...}``) names.

Two catalogues of real parts come with the package (``springbalance/data/catalogues/``, format:
:mod:`springbalance.io.catalogue`; docs/guides/coils-and-stock.md, "Stock springs"):

========== ==================================================================================
name       parts
========== ==================================================================================
``ms24585`` MS24585 (SAE-AS24585) helical compression springs, closed and ground ends, music
           wire ``MS24585-1`` … ``-527`` and 302 stainless ``MS24585C1`` … ``C527`` (1054 parts)
``ms24586`` MS24586 (SAE-AS24586) helical extension springs, full hooks, music wire
           ``MS24586-1`` … ``-354`` and 302 stainless ``MS24586C1`` … ``C354`` (708 parts)
========== ==================================================================================

Their dimensions (wire, outer diameter, coils, free length or initial tension) are the standards'
tables as transcribed by the MIT-licensed ODOP project (``LICENSE-ODOP.txt`` and ``README.md``
beside the data), converted to SI units by ``tools/ms_catalogues/make_ms_catalogues.py``; rate and
largest load follow from the project's material rules.

:func:`load_stock` reads a *stock spec*: a catalogue name, a CSV path, or several of them (a list,
or one string separated by commas), and returns their parts together.
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

from springbalance.design.stock import StockPart
from springbalance.errors import InputError
from springbalance.io.catalogue import read_catalogue

__all__ = ["STANDARD_CATALOGUES", "load_stock", "standard_catalogue_path"]

#: the folder of the packaged catalogues (package data: pyproject.toml [tool.setuptools.package-data])
DATA = Path(__file__).resolve().parents[1] / "data" / "catalogues"
#: name → what it holds (the packaged file is ``data/catalogues/<name>.csv``)
STANDARD_CATALOGUES = {
    "ms24585": "MS24585 (SAE-AS24585) helical compression springs, music wire and 302 stainless",
    "ms24586": "MS24586 (SAE-AS24586) helical extension springs, music wire and 302 stainless",
}


def standard_catalogue_path(name: str) -> Path:
    """The packaged CSV file of the standard catalogue ``name`` (a key of :data:`STANDARD_CATALOGUES`,
    any case)."""
    key = name.strip().lower()
    if key not in STANDARD_CATALOGUES:
        raise InputError(f"unknown standard stock catalogue {name!r}; valid: {', '.join(STANDARD_CATALOGUES)}")
    return DATA / f"{key}.csv"


def load_stock(spec: str | Path | Sequence[str | Path], base_dir: str | Path | None = None) -> list[StockPart]:
    """The parts of the catalogues that ``spec`` names, in order: each entry a standard catalogue's name
    (``ms24585``, ``ms24586``; any case) or the path of a CSV catalogue (relative to ``base_dir`` when
    given). A string may hold several entries separated by commas (``"ms24585,ms24586"``).

    Raises :class:`InputError` (one line) for an empty spec, an entry that is neither a name nor an
    existing file, a bad catalogue (:func:`~springbalance.io.catalogue.read_catalogue`), or a part number
    that two catalogues share.
    """
    entries = _entries(spec)
    parts: list[StockPart] = []
    source: dict[str, str] = {}
    for entry in entries:
        label = entry
        if entry.lower() in STANDARD_CATALOGUES:
            path = standard_catalogue_path(entry)
        else:
            path = Path(entry) if base_dir is None or Path(entry).is_absolute() else Path(base_dir) / entry
            if not path.is_file() and not path.suffix and "/" not in entry and "\\" not in entry:
                raise InputError(
                    f"unknown stock catalogue {entry!r}: not a standard catalogue "
                    f"({', '.join(STANDARD_CATALOGUES)}) and no such file"
                )
            label = str(path)
        for part in read_catalogue(path):
            if part.part_number in source:
                raise InputError(
                    f"stock catalogues {source[part.part_number]} and {label} both hold part {part.part_number!r}"
                )
            source[part.part_number] = label
            parts.append(part)
    return parts


def _entries(spec: str | Path | Sequence[str | Path]) -> list[str]:
    """The entries of a stock spec (module docstring), stripped; InputError when there are none."""
    if isinstance(spec, Path):
        return [str(spec)]
    items = spec.split(",") if isinstance(spec, str) else [str(item) for item in spec]
    entries = [item.strip() for item in items if str(item).strip()]
    named = [entry.lower() if entry.lower() in STANDARD_CATALOGUES else entry for entry in entries]
    if not entries or (isinstance(spec, str) and len(entries) != len(items)):
        raise InputError(
            f"stock catalogue {str(spec)!r}: expected a catalogue name ({', '.join(STANDARD_CATALOGUES)}), "
            "a CSV file, or several separated by commas"
        )
    return list(dict.fromkeys(named))  # a catalogue named twice is read once
