"""What each key of a case measures, from the case schema's ``x-quantity`` annotations.

Every numeric key of ``case.schema.yaml`` says what it measures with the custom keyword
``x-quantity`` (JSON-schema validators ignore it): a :data:`gridlib.units.QUANTITIES` member
(``length``, ``angle``, ``pressure``, ``rate``, ``time``, ``permeability``, ``fraction``,
``dimensionless``, ...), whose unit follows from the case's unit system
(:meth:`gridlib.units.UnitSystem.unit`); ``count`` for numbers without a unit (cell and layer
counts, seeds); ``inherit`` for a value that measures what the key it belongs to measures (a
property's ``constant`` or ``field.mean``: a fraction under ``porosity``, mD under
``permeability``); or ``measure`` for a qc rule's limit (``qc.0.max``), which measures what the
cell-quality measure its ``quantity`` names measures (degrees for an angle; known from the case's
data only). ``x-unit-system`` beside it fixes the system whatever the case's
(``carman_kozeny.grain_diameter`` is in m, ``report_days`` in days). A row whose columns measure
different things (a survey station: md, inclination, azimuth) gives each column its own
``x-quantity`` under ``prefixItems``; its keys name the column (``wells.0.survey.stations.0.1``, an
inclination).

A case's keys are in the case's unit system: METRIC for every grid gridlib builds, the deck's
own (FIELD for the sample ``spe9``) for a ``deck`` case, whose coordinates, depths, pressures and
rates are the deck's.

>>> from gridlib.units import FIELD, METRIC
>>> key_quantity("faults.0.throw").unit(METRIC), key_quantity("simulation.initial.pressure").unit(FIELD)
('m', 'psia')
>>> key_quantity("petrophysics.permeability.field.mean").unit(FIELD), key_quantity("grid.dims").unit(METRIC)
('mD', None)
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import Any

import jsonschema

from ..errors import InputError
from ..units import QUANTITIES, UNIT_SYSTEMS, UnitSystem, unit_system
from . import SCHEMA_FILE, shared_schema

MARK = "x-quantity"
SYSTEM_MARK = "x-unit-system"
COUNT = "count"  # a number without a unit: a count, a seed
INHERIT = "inherit"  # what the enclosing key measures
MEASURE = "measure"  # a qc rule's limit: what the measure its sibling `quantity` names measures
MARKS = (*QUANTITIES, COUNT, INHERIT, MEASURE)


@dataclass(frozen=True)
class KeyQuantity:
    """What a key measures: ``quantity`` (a :data:`~gridlib.units.QUANTITIES` member; None: no
    unit, a count, a text, or a mapping of keys that measure different things) and, where the
    key's unit does not follow the case's system, the system it is in (``unit_system``)."""

    quantity: str | None
    unit_system: str | None = None

    def unit(self, system: UnitSystem | str | None, griddim: int = 3) -> str | None:
        """The key's unit in a case of unit system ``system`` (None: no unit)."""
        if self.quantity is None:
            return None
        return unit_system(self.unit_system or system).unit(self.quantity, griddim)


@dataclass(frozen=True)
class _At:
    """A schema node reached along a key: ``context`` the quantity of the nearest enclosing
    node that states one (what ``inherit`` takes), ``quantity`` what this node measures."""

    node: Any
    data: Any
    context: KeyQuantity | None
    quantity: KeyQuantity | None


def _resolve_ref(ref: str, root: Mapping[str, Any]) -> Any:
    node: Any = root
    for part in ref.removeprefix("#/").split("/"):
        node = node[part]
    return node


def _applies(condition: Any, data: Any) -> bool:
    """An allOf member's ``if`` holds for the case's ``data`` (every branch applies without it)."""
    return data is None or jsonschema.Draft202012Validator(condition).is_valid(data)


def _expand(at: _At, root: Mapping[str, Any]) -> Iterator[tuple[_At, bool]]:
    """``at`` and every node that applies to the same value: $ref targets, allOf members (the
    ``then`` of those whose ``if`` holds), oneOf/anyOf alternatives; each with whether it is a
    leaf of that tree (its quantity is the last word: a $ref target's annotation overrides the
    referring key's absence of one)."""
    stack = [at]
    while stack:
        here = stack.pop()
        node = here.node
        if not isinstance(node, dict):
            continue
        mark = node.get(MARK)
        if mark == INHERIT:
            here = _At(node, here.data, here.context, here.context)
        elif mark == MEASURE:
            pass  # resolved by _step from the rule's `quantity`
        elif mark is not None:
            own = KeyQuantity(None if mark == COUNT else mark, node.get(SYSTEM_MARK))
            here = _At(node, here.data, own, own)
        follow = []
        if "$ref" in node:
            follow.append(_resolve_ref(node["$ref"], root))
        for member in node.get("allOf", ()):
            if "if" in member:
                if _applies(member["if"], here.data):
                    follow.append(member.get("then"))
            else:
                follow.append(member)
        follow += [*node.get("oneOf", ()), *node.get("anyOf", ())]
        yield here, not follow
        stack += [_At(sub, here.data, here.context, here.quantity) for sub in follow]


def _step(at: _At, part: str | int) -> _At | None:
    """The node of key component ``part`` below ``at`` (a property, or an array's item)."""
    node, data = at.node, at.data
    if isinstance(part, int):
        prefix = node.get("prefixItems")
        item_node = prefix[part] if isinstance(prefix, list) and part < len(prefix) else node.get("items")
        if not isinstance(item_node, dict):
            return None
        item = data[part] if isinstance(data, list) and part < len(data) else None
        return _At(item_node, item, at.context, at.quantity)  # an item measures what its array does
    properties = node.get("properties")
    if not isinstance(properties, dict) or part not in properties:
        return None
    value = data.get(part) if isinstance(data, dict) else None
    sub = properties[part]
    if isinstance(sub, dict) and sub.get(MARK) == MEASURE:
        return _At(sub, value, at.context, _measure_quantity(data))
    return _At(sub, value, at.context, None)  # a key measures what it says, or nothing


def _measure_quantity(rule: Any) -> KeyQuantity | None:
    """What the limit of the qc ``rule`` (a case's data, or None) measures: the quantity of the
    measure its ``quantity`` names (:data:`gridlib.quality.MEASURES`; the same in every unit
    system); None (no unit known) without the case's data."""
    from ..quality import MEASURES

    name = rule.get("quantity") if isinstance(rule, dict) else None
    unit = next((m.unit for m in MEASURES if m.name == name), None)
    return None if unit is None else KeyQuantity(unit, "METRIC")


def key_quantity(
    key: str, case: Mapping[str, Any] | None = None, schema: Mapping[str, Any] | None = None
) -> KeyQuantity:
    """What the dotted ``key`` (as a study varies it: ``faults.0.throw``, list items by their
    0-based index) of a case measures, through the schema's $ref, items, allOf/if-then and
    oneOf. ``case``: the case's data, which picks the ``grid.type`` (and site ``pattern``)
    branch; without it every branch counts, and a key that would measure different things in
    different branches is an InputError, as is a key the schema does not have."""
    root = shared_schema(SCHEMA_FILE) if schema is None else schema
    parts: list[str | int] = [int(p) if p.isdigit() else p for p in key.split(".")]
    states = list(_expand(_At(root, case, None, None), root))
    for part in parts:
        stepped = [s for s in (_step(at, part) for at, _ in states) if s is not None]
        states = [e for s in stepped for e in _expand(s, root)]
        if not states:
            raise InputError(f"{key}: not a key of the case schema")
    found = {at.quantity or KeyQuantity(None) for at, leaf in states if leaf}  # None: no unit there
    if len(found) > 1:
        kinds = sorted(
            f"{q.quantity or 'no unit'}" + (f" ({q.unit_system})" if q.unit_system else "") for q in found
        )
        raise InputError(f"{key}: measures {' or '.join(kinds)} depending on the grid; give the case")
    return next(iter(found), KeyQuantity(None))


def key_unit(key: str, system: UnitSystem | str | None, case: Mapping[str, Any] | None = None) -> str | None:
    """The unit of ``key`` in a case of unit system ``system`` (None: no unit)."""
    return key_quantity(key, case).unit(system)


def _is_number(node: Mapping[str, Any]) -> bool:
    kinds = node.get("type")
    kinds = kinds if isinstance(kinds, list) else [kinds]
    return "number" in kinds or "integer" in kinds


def annotation_problems(schema: Mapping[str, Any] | None = None) -> list[str]:
    """Where the schema's annotations are missing or wrong, one line each (empty: none): a
    numeric key (or an array of numbers) without ``x-quantity``, unless it is an item or a
    oneOf alternative of an annotated node; an ``x-quantity`` or ``x-unit-system`` value that
    is not one :data:`MARKS` or :data:`gridlib.units.UNIT_SYSTEMS` names."""
    root = shared_schema(SCHEMA_FILE) if schema is None else schema
    problems: list[str] = []

    def visit(node: Any, where: str, covered: bool) -> None:
        if isinstance(node, list):
            for i, sub in enumerate(node):
                visit(sub, f"{where}/{i}", covered)
            return
        if not isinstance(node, dict):
            return
        mark = node.get(MARK)
        if mark is not None and mark not in MARKS:
            problems.append(f"{where}: {MARK}: {mark!r} is none of {', '.join(MARKS)}")
        system = node.get(SYSTEM_MARK)
        if system is not None and system not in UNIT_SYSTEMS:
            problems.append(f"{where}: {SYSTEM_MARK}: {system!r} is none of {', '.join(UNIT_SYSTEMS)}")
        covered = covered or mark is not None
        items = node.get("items")
        numbers = _is_number(node) or (isinstance(items, dict) and _is_number(items))
        if numbers and not covered:
            problems.append(f"{where}: a number without {MARK} (what does it measure?)")
            covered = True  # said once, not again for its items
        for name, sub in (node.get("properties") or {}).items():
            visit(sub, f"{where}/properties/{name}", False)  # a key states its own quantity
        for name, sub in (node.get("$defs") or {}).items():
            visit(sub, f"{where}/$defs/{name}", False)
        for keyword in ("items", "prefixItems", "oneOf", "anyOf", "allOf", "then", "else"):
            if keyword in node:
                visit(node[keyword], f"{where}/{keyword}", covered)

    visit(root, "#", False)
    return problems


def numeric_keys(schema: Mapping[str, Any] | None = None) -> dict[str, KeyQuantity]:
    """Every dotted key of the schema whose value is a number or a list of numbers (list items
    as ``0``: ``faults.0.throw``), in every branch, with what it measures (:func:`key_quantity`;
    the keys config/README.md's ``unit`` column must cover)."""
    root = shared_schema(SCHEMA_FILE) if schema is None else schema
    found: dict[str, KeyQuantity] = {}

    def visit(states: list[_At], path: tuple[str, ...]) -> None:
        expanded = [e for at in states for e in _expand(at, root)]
        if path and any(_is_number(at.node) for at, _ in expanded):
            found[".".join(path)] = key_quantity(".".join(path), schema=root)
        names = {n for at, _ in expanded for n in (at.node.get("properties") or {})}
        for name in sorted(names):
            visit([s for s in (_step(at, name) for at, _ in expanded) if s], (*path, name))
        # the columns of a row (a survey station: md, inclination, azimuth), else one item for all
        positions = max((len(at.node.get("prefixItems") or ()) for at, _ in expanded), default=0)
        if any(isinstance(at.node.get("items"), dict) for at, _ in expanded):
            positions = max(positions, 1)
        for k in range(positions):
            visit([s for s in (_step(at, k) for at, _ in expanded) if s], (*path, str(k)))

    visit([_At(root, None, None, None)], ())
    return found
