"""Reading config files: YAML where ``1e4`` is a number and a key may appear only once; JSON likewise.

PyYAML follows YAML 1.1, whose floats need a dot and a signed exponent (``1.0e+4``): plain
``1e4`` or ``2E-3`` would be read as strings. :class:`ConfigLoader` also reads these exponent
forms as numbers, and takes booleans from YAML 1.2 (``true``/``false``; ``on``, ``off``, ``yes``
and ``no`` stay strings). Implicit resolvers apply to *plain* scalars only, so a quoted ``"2e3"`` stays
the string ``2e3``.

A mapping that gives the same key twice is an error (:class:`DuplicateKeyError`, naming the key,
its key path and both lines) rather than the last value silently winning; ``<<`` merge keys
still work, and a key given explicitly may override a merged one.
"""

from __future__ import annotations

import json
import re

import yaml

FLOAT_TAG = "tag:yaml.org,2002:float"
BOOL_TAG = "tag:yaml.org,2002:bool"
#: Booleans as YAML 1.2 has them: ``true``/``false`` only. YAML 1.1 also reads yes/no/on/off as
#: booleans, which would turn an anchor's ``on: floor`` key into ``True: floor``.
BOOL = re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$")
MERGE_TAG = "tag:yaml.org,2002:merge"

#: YAML 1.1 floats (PyYAML's resolver), plus exponents without a dot or without a sign.
FLOAT = re.compile(r"""^(?:[-+]?(?:[0-9][0-9_]*)\.[0-9_]*(?:[eE][-+]?[0-9]+)?
                    |[-+]?(?:[0-9][0-9_]*)(?:[eE][-+]?[0-9]+)
                    |[-+]?\.[0-9][0-9_]*(?:[eE][-+]?[0-9]+)?
                    |[-+]?[0-9][0-9_]*(?::[0-5]?[0-9])+\.[0-9_]*
                    |[-+]?\.(?:inf|Inf|INF)
                    |\.(?:nan|NaN|NAN))$""", re.X)


class DuplicateKeyError(yaml.YAMLError):
    """A mapping gives ``key`` twice.

    Attributes:
        key: the repeated key; path: key path of the mapping (``""`` at the top);
        line, first_line: 1-based lines of the repeat and of the first occurrence (None in JSON).
    """

    def __init__(self, key, path: str = "", line: int | None = None, first_line: int | None = None):
        self.key, self.path, self.line, self.first_line = key, path, line, first_line
        where = f" at line {line} (first at line {first_line})" if line is not None else ""
        super().__init__(f"duplicate key {key!r}{where}")


class ConfigLoader(yaml.SafeLoader):
    """:class:`yaml.SafeLoader` with exponent-form floats and duplicate keys rejected."""

    yaml_implicit_resolvers = {first: [(tag, regexp) for tag, regexp in resolvers if tag not in (FLOAT_TAG, BOOL_TAG)]
                               for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()}

    def get_single_data(self):
        node = self.get_single_node()
        if node is None:
            return None
        self._check_duplicate_keys(node, "", set())
        return self.construct_document(node)

    def _check_duplicate_keys(self, node, path: str, seen_nodes: set) -> None:
        """Walk the composed document; raise :class:`DuplicateKeyError` at the first repeated key."""
        if id(node) in seen_nodes:  # an alias of a node already walked
            return
        seen_nodes.add(id(node))
        if isinstance(node, yaml.SequenceNode):
            for index, item in enumerate(node.value):
                self._check_duplicate_keys(item, f"{path}[{index}]", seen_nodes)
        elif isinstance(node, yaml.MappingNode):
            lines = {}
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


def load_yaml(text: str):
    """Parse YAML ``text`` with :class:`ConfigLoader` (raises :class:`yaml.YAMLError`)."""
    return yaml.load(text, Loader=ConfigLoader)  # noqa: S506 (a SafeLoader subclass)


def load_json(text: str):
    """Parse JSON ``text``; an object that repeats a key raises :class:`DuplicateKeyError`."""
    return json.loads(text, object_pairs_hook=_unique_pairs)


def _unique_pairs(pairs) -> dict:
    record = {}
    for key, value in pairs:
        if key in record:
            raise DuplicateKeyError(key)
        record[key] = value
    return record
