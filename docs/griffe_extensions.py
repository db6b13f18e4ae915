"""Griffe extension for the API reference (loaded by mkdocs.yml, not part of the site).

The subpackages re-export their main names (``springbalance.springs.ExtensionSpring`` is
``springbalance.springs.laws.extension.ExtensionSpring``). mkdocstrings would render such a
name twice: at the package and in the module that defines it. This extension marks every
re-export as non-public, so each object is rendered once, in its own module's section.

The docstrings cite other objects with reStructuredText roles (``:func:`...```) and hold ``.. math::``
and ``.. code-block::`` blocks, which the Google-style renderer would print as written: :class:`SphinxRoles`
turns them into inline code and fenced blocks.
"""

from __future__ import annotations

import re
import textwrap
from typing import Any

from griffe import Extension, Module, Object


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


_ROLE = re.compile(r":(?:func|class|meth|mod|attr|data|exc|obj|math):`(~?)([^`]+)`")
_DIRECTIVE = re.compile(r"^(?P<indent>[ \t]*)\.\. (?P<kind>code-block|math)::[ \t]*(?P<rest>.*?)[ \t]*$")


def markdown_docstring(text: str) -> str:
    """The reStructuredText of a docstring made readable in Markdown: a role (``:func:`~a.b.c```) becomes
    inline code (`` `c` ``), a ``.. code-block:: python`` or ``.. math::`` block a fenced code block."""
    text = _ROLE.sub(lambda match: f"`{match.group(2).rsplit('.', 1)[-1] if match.group(1) else match.group(2)}`", text)
    lines, out, index = text.splitlines(), [], 0
    while index < len(lines):
        match = _DIRECTIVE.match(lines[index])
        if match is None:
            out.append(lines[index])
            index += 1
            continue
        indent = match.group("indent")
        block, index = [], index + 1
        while index < len(lines) and (not lines[index].strip() or lines[index].startswith(indent + " ")):
            block.append(lines[index])
            index += 1
        while block and not block[-1].strip():
            block.pop()
        body = textwrap.dedent("\n".join(line for line in block)).strip("\n")
        language, rest = ("text", match.group("rest")) if match.group("kind") == "math" else (match.group("rest"), "")
        body = f"{rest}\n{body}".strip("\n") if rest else body
        out += [f"{indent}```{language}", *[indent + line for line in body.splitlines()], f"{indent}```", ""]
    return "\n".join(out)


class SphinxRoles(Extension):
    """Render the docstrings' reStructuredText roles and directives as Markdown (:func:`markdown_docstring`)."""

    def on_package(self, *, pkg: Module, **kwargs: Any) -> None:
        self._rewrite(pkg)

    def _rewrite(self, obj: Object) -> None:
        if obj.docstring is not None:
            obj.docstring.value = markdown_docstring(obj.docstring.value)
        for member in obj.members.values():
            if not member.is_alias:
                self._rewrite(member)
