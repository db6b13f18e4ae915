"""Reading config files: YAML where ``1e4`` is a number and a key may appear only once; JSON likewise.

PyYAML follows YAML 1.1, whose floats need a dot and a signed exponent (``1.0e+4``): plain
``1e4`` or ``2E-3`` would be read as strings. :class:`ConfigLoader` also reads these exponent
forms as numbers, and takes booleans from YAML 1.2 (``true``/``false``; ``on``, ``off``, ``yes``
and ``no`` stay strings). Implicit resolvers apply to *plain* scalars only, so a quoted ``"2e3"`` stays
the string ``2e3``.

A mapping that gives the same key twice is an error (:class:`DuplicateKeyError`, naming the key,
its key path and both lines) rather than the last value silently winning; ``<<`` merge keys
still work, and a key given explicitly may override a merged one.

Both readers are bounded (:class:`LimitError`): a document nests at most :data:`MAX_DEPTH`
collections deep, and holds at most :data:`MAX_VALUES` values once its aliases are expanded (an
"alias bomb" of nested ``*a`` references is refused before anything walks it); a recursive alias
is refused. The size of the file is bounded by its reader (:data:`MAX_BYTES`).
"""

from __future__ import annotations

import json
import re
from typing import Any

import yaml

FLOAT_TAG = "tag:yaml.org,2002:float"
BOOL_TAG = "tag:yaml.org,2002:bool"
#: Booleans as YAML 1.2 has them: ``true``/``false`` only. YAML 1.1 also reads yes/no/on/off as
#: booleans, which would turn an anchor's ``on: floor`` key into ``True: floor``.
BOOL = re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$")
MERGE_TAG = "tag:yaml.org,2002:merge"

#: the largest config file read [bytes]
MAX_BYTES = 16 << 20
#: the deepest nesting of mappings and lists
MAX_DEPTH = 64
#: the most values (scalars, lists and mappings) of a document, its aliases expanded
MAX_VALUES = 2_000_000

#: YAML 1.1 floats (PyYAML's resolver), plus exponents without a dot or without a sign.
FLOAT = re.compile(
    r"""^(?:[-+]?(?:[0-9][0-9_]*)\.[0-9_]*(?:[eE][-+]?[0-9]+)?
                    |[-+]?(?:[0-9][0-9_]*)(?:[eE][-+]?[0-9]+)
                    |[-+]?\.[0-9][0-9_]*(?:[eE][-+]?[0-9]+)?
                    |[-+]?[0-9][0-9_]*(?::[0-5]?[0-9])+\.[0-9_]*
                    |[-+]?\.(?:inf|Inf|INF)
                    |\.(?:nan|NaN|NAN))$""",
    re.X,
)


class DuplicateKeyError(yaml.YAMLError):
    """A mapping gives ``key`` twice.

    Attributes:
        key: the repeated key; path: key path of the mapping (``""`` at the top);
        line, first_line: 1-based lines of the repeat and of the first occurrence (None in JSON).
    """

    def __init__(self, key: Any, path: str = "", line: int | None = None, first_line: int | None = None) -> None:
        self.key, self.path, self.line, self.first_line = key, path, line, first_line
        where = f" at line {line} (first at line {first_line})" if line is not None else ""
        super().__init__(f"duplicate key {key!r}{where}")


class LimitError(yaml.YAMLError):
    """A document past a bound of the reader (nesting depth, expanded size, recursive alias)."""


class ConfigLoader(yaml.SafeLoader):
    """:class:`yaml.SafeLoader` with exponent-form floats, duplicate keys rejected and bounded documents."""

    yaml_implicit_resolvers = {
        first: [(tag, regexp) for tag, regexp in resolvers if tag not in (FLOAT_TAG, BOOL_TAG)]
        for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
    }

    def compose_node(self, parent: yaml.Node | None, index: Any) -> yaml.Node | None:
        depth = getattr(self, "_depth", 0)
        if depth > MAX_DEPTH:
            mark = self.peek_event().start_mark
            raise LimitError(f"nested more than {MAX_DEPTH} levels deep at line {mark.line + 1}")
        self._depth = depth + 1
        try:
            return super().compose_node(parent, index)
        finally:
            self._depth = depth

    def get_single_data(self) -> Any:
        node = self.get_single_node()
        if node is None:
            return None
        _expanded_size(node, {}, set())
        self._check_duplicate_keys(node, "", set())
        return self.construct_document(node)

    def _check_duplicate_keys(self, node: yaml.Node, path: str, seen_nodes: set[int]) -> None:
        """Walk the composed document; raise :class:`DuplicateKeyError` at the first repeated key."""
        if id(node) in seen_nodes:  # an alias of a node already walked
            return
        seen_nodes.add(id(node))
        if isinstance(node, yaml.SequenceNode):
            for index, item in enumerate(node.value):
                self._check_duplicate_keys(item, f"{path}[{index}]", seen_nodes)
        elif isinstance(node, yaml.MappingNode):
            lines: dict[Any, int] = {}
            for key_node, value_node in node.value:
                if key_node.tag == MERGE_TAG:
                    self._check_duplicate_keys(value_node, path, seen_nodes)
                    continue
                key = self.construct_object(key_node, deep=True)
                line = key_node.start_mark.line + 1
                try:
                    if key in lines:
                        raise DuplicateKeyError(key, path, line, lines[key])
                    lines[key] = line
                except TypeError:  # an unhashable (complex) key: the constructor reports it
                    continue
                self._check_duplicate_keys(value_node, f"{path}.{key}" if path else str(key), seen_nodes)


ConfigLoader.add_implicit_resolver(FLOAT_TAG, FLOAT, list("-+0123456789."))
ConfigLoader.add_implicit_resolver(BOOL_TAG, BOOL, list("tTfF"))


def _expanded_size(node: yaml.Node, sizes: dict[int, int], open_nodes: set[int]) -> int:
    """Number of values under ``node`` with every alias expanded; :class:`LimitError` past
    :data:`MAX_VALUES` or for a recursive alias. Shared nodes are counted once per use but walked once."""
    key = id(node)
    if key in sizes:
        return sizes[key]
    if key in open_nodes:
        raise LimitError(f"a recursive alias at line {node.start_mark.line + 1}: a value cannot contain itself")
    open_nodes.add(key)
    size = 1
    if isinstance(node, yaml.SequenceNode):
        size += sum(_expanded_size(item, sizes, open_nodes) for item in node.value)
    elif isinstance(node, yaml.MappingNode):
        size += sum(_expanded_size(k, sizes, open_nodes) + _expanded_size(v, sizes, open_nodes) for k, v in node.value)
    open_nodes.discard(key)
    if size > MAX_VALUES:
        raise LimitError(
            f"the document expands to more than {MAX_VALUES} values (through aliases at or below line "
            f"{node.start_mark.line + 1})"
        )
    sizes[key] = size
    return size


def load_yaml(text: str) -> Any:
    """Parse YAML ``text`` with :class:`ConfigLoader` (raises :class:`yaml.YAMLError`, :class:`LimitError`
    past the bounds)."""
    return yaml.load(text, Loader=ConfigLoader)


def load_json(text: str) -> Any:
    """Parse JSON ``text``; an object that repeats a key raises :class:`DuplicateKeyError`, a document
    nested deeper than :data:`MAX_DEPTH` :class:`LimitError`."""
    try:
        record = json.loads(text, object_pairs_hook=_unique_pairs)
    except RecursionError:
        raise LimitError(f"nested more than {MAX_DEPTH} levels deep") from None
    _check_depth(record)
    return record


def _check_depth(record: Any) -> None:
    """:class:`LimitError` when lists and objects in ``record`` nest deeper than :data:`MAX_DEPTH`."""
    level = [record]
    for depth in range(MAX_DEPTH + 2):
        children: list[Any] = []
        for value in level:
            if isinstance(value, dict):
                children.extend(value.values())
            elif isinstance(value, list):
                children.extend(value)
        if not children:
            return
        if depth >= MAX_DEPTH:
            raise LimitError(f"nested more than {MAX_DEPTH} levels deep")
        level = children


def _unique_pairs(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    record: dict[str, Any] = {}
    for key, value in pairs:
        if key in record:
            raise DuplicateKeyError(key)
        record[key] = value
    return record
