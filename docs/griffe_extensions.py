"""Griffe extension for the API reference (loaded by mkdocs.yml, not part of the site).

The subpackages re-export their main names (``springbalance.springs.ExtensionSpring`` is
``springbalance.springs.laws.extension.ExtensionSpring``). mkdocstrings would render such a
name twice: at the package and in the module that defines it. This extension marks every
re-export as non-public, so each object is rendered once, in its own module's section.
"""

from __future__ import annotations

from typing import Any

from griffe import Extension, Module


class DefinedOnce(Extension):
    """Hide the aliases (re-exports) of a package and of each of its submodules."""

    def on_package(self, *, pkg: Module, **kwargs: Any) -> None:
        self._hide_aliases(pkg)

    def _hide_aliases(self, module: Module) -> None:
        for member in module.members.values():
            if member.is_alias:
                member.public = False
            elif member.is_module:
                self._hide_aliases(member)
