"""Pinocchio models of URDF text: the parse (errors as one-line :class:`~springbalance.errors.InputError`),
pseudo-bases added (:mod:`springbalance.model.pseudo_bases`), and the warning for mimic joints loaded uncoupled."""

from __future__ import annotations

import warnings
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import pinocchio as pin

from springbalance.errors import InputError
from springbalance.model.mimic_order import ordered_for_pinocchio, restore_names
from springbalance.model.native import quiet_native_stderr
from springbalance.model.pseudo_bases import PseudoBase, pseudo_base_model

__all__ = ["build_model"]


def build_model(
    text: str, where: str, mimic: bool, bases: list[PseudoBase], path: Path | None, label: str
) -> pin.Model:
    """The Pinocchio model of a URDF (read from ``path`` when given, else from ``text``), pseudo-bases added;
    with ``mimic``, a mimic joint that Pinocchio would number before its primary is reordered first
    (:mod:`springbalance.model.mimic_order`)."""
    if bases:
        return pseudo_base_model(text, bases, where, mimic)
    reordered = ordered_for_pinocchio(text, where) if mimic else None
    try:
        with quiet_native_stderr():
            if reordered is not None:
                model = pin.buildModelFromXML(reordered[0], mimic=True)
            elif path is not None:
                model = pin.buildModelFromUrdf(str(path), mimic=mimic)
            else:
                model = pin.buildModelFromXML(text, mimic=mimic)
    except Exception as exc:  # Pinocchio raises RuntimeError/ValueError with C++ text
        raise InputError(f"{where} could not be parsed: {one_line(exc)}") from None
    if reordered is not None:
        restore_names(model, reordered[1])
    if not mimic:
        _warn_unused_mimic(text, label)
    return model


def _warn_unused_mimic(text: str, where: str) -> None:
    """Warn when a URDF declares mimic joints but is loaded with ``mimic=False`` (they become independent)."""
    try:
        root = ElementTree.fromstring(text)
    except ElementTree.ParseError:
        return
    names = [joint.get("name", "?") for joint in root.iter("joint") if joint.find("mimic") is not None]
    if names:
        warnings.warn(
            f"{where} declares mimic joints ({', '.join(names)}); they are loaded as independent joints. "
            "Pass mimic=True (config: mechanism.mimic: true; `springbalance inspect --mimic`) to couple them "
            "to their primary joints.",
            stacklevel=4,
        )


def one_line(exc: Exception) -> str:
    text = " ".join(str(exc).split())
    return text[:300] if text else type(exc).__name__
